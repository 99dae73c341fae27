#!/usr/bin/env python3
"""How fast events cross machines on a PostgreSQL store (a benchmark, not a test).

    serve/bench/event_delay.py BINARY POSTGRES_URL [JOBS]

Starts two fronts (`gapack serve --workers 0`) and one worker process
(`gapack worker --workers 1`) on the store at POSTGRES_URL (an empty
database) and one shared data folder. For each of JOBS jobs (default 40,
the tiny CSV-only square, one at a time): opens the event stream on front
B, submits the job on front A, and times, from the submit's answer, the
`running` event (front A's NOTIFY wakes the worker, whose claim's event
NOTIFY reaches front B's stream) and the final `succeeded` event on B's
stream. Prints the median and the 90th and 99th percentiles (ms) of both;
with notifications lost, each would wait for the 0.5 s idle poll of the
worker and the 5 s poll of the stream.
"""
import http.client
import json
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time

SQUARE = ('seed = 3\n[domain]\nshape = "rectangle"\nwidth = 20\nheight = 20\n'
          '[grading]\nuniform = [1.0, 2.0]\n[output]\nformats = ["csv"]\n')


def start(args, log):
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=log, text=True)
    return proc


def front(binary, store, data, log):
    proc = start([binary, 'serve', '--listen', '127.0.0.1:0', '--workers', '0',
                  '--store', store, '--data', data], log)
    line = proc.stdout.readline().strip()
    assert line.startswith('listening on http://'), line
    host, port = line.removeprefix('listening on http://').split(':')
    return proc, (host, int(port))


def percentile(values, q):
    values = sorted(values)
    return values[min(len(values) - 1, int(q * len(values)))]


def main():
    binary, store = sys.argv[1], sys.argv[2]
    jobs = int(sys.argv[3]) if len(sys.argv) > 3 else 40
    scratch = tempfile.mkdtemp(prefix='gapack-event-delay-')
    data = os.path.join(scratch, 'data')
    log = open(os.path.join(scratch, 'log'), 'w')
    a, addr_a = front(binary, store, data, log)
    b, addr_b = front(binary, store, data, log)
    w = start([binary, 'worker', '--store', store, '--data', data, '--workers', '1'], log)
    running, done = [], []
    try:
        time.sleep(1.0)
        for i in range(jobs):
            conn = http.client.HTTPConnection(*addr_a)
            conn.request('POST', f'/api/v1/jobs?kind=pack&seed={i}', SQUARE,
                         {'Content-Type': 'application/toml'})
            r = conn.getresponse()
            body = json.loads(r.read())
            assert r.status == 201, body
            submitted = time.perf_counter()
            stream = http.client.HTTPConnection(*addr_b)
            stream.request('GET', f"/api/v1/jobs/{body['id']}/events")
            s = stream.getresponse()
            assert s.status == 200
            seen_running = None
            for raw in s:
                line = raw.decode().strip()
                if not line.startswith('data:'):
                    continue
                event = json.loads(line[5:])
                if event.get('event') != 'state':
                    continue
                now = time.perf_counter()
                if event['state'] == 'running' and seen_running is None:
                    seen_running = now - submitted
                if event['state'] in ('succeeded', 'failed', 'cancelled'):
                    assert event['state'] == 'succeeded', event
                    running.append(seen_running * 1e3)
                    done.append((now - submitted) * 1e3)
                    break
            stream.close()
    finally:
        for p in (a, b, w):
            p.send_signal(signal.SIGTERM)
        for p in (a, b, w):
            p.wait(timeout=30)
    for name, values in (('submit on A -> running on B', running),
                         ('submit on A -> succeeded on B', done)):
        print(f'{name}: median {statistics.median(values):.1f} ms, '
              f'p90 {percentile(values, 0.9):.1f} ms, p99 {percentile(values, 0.99):.1f} ms '
              f'({len(values)} jobs)')


if __name__ == '__main__':
    main()
