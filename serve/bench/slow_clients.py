"""Slow and broken clients against a running `gapack serve`.

    python3 serve/bench/slow_clients.py HOST:PORT trickle [N]      # N sockets (50) trickle
        their headers a byte a second; three normal requests are timed
    python3 serve/bench/slow_clients.py HOST:PORT incomplete [S]   # a body of 100 bytes
        declared, 9 sent: when is the connection closed (waits up to S s, 120)
    python3 serve/bench/slow_clients.py HOST:PORT slowheaders      # headers never ended
    python3 serve/bench/slow_clients.py HOST:PORT oversize [S]     # 1 MiB + 1 declared, 3 sent
"""
import socket, sys, time, threading

host, port = sys.argv[1].split(":"); port = int(port)
what = sys.argv[2]

def connect():
    s = socket.create_connection((host, port))
    s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return s

def first(data):
    return data.split(b'\r\n')[0]

def read_all(s, limit):
    s.settimeout(limit)
    data = b""; err = None
    try:
        while True:
            chunk = s.recv(65536)
            if not chunk: break
            data += chunk
    except Exception as e:
        err = type(e).__name__
    return data, err

if what == "trickle":
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 50
    stop = False
    socks = []
    for i in range(n):
        socks.append(connect())
    line = f"GET /healthz HTTP/1.1\r\nHost: {host}\r\nX-Slow: " + "a" * 200
    def trickle():
        i = 0
        while not stop and i < len(line):
            for s in list(socks):
                try: s.send(line[i].encode())
                except Exception: socks.remove(s)
            i += 1
            time.sleep(1.0)
    t = threading.Thread(target=trickle, daemon=True); t.start()
    time.sleep(3.0)
    for k in range(3):
        start = time.monotonic()
        s = connect()
        s.sendall(f"GET /healthz HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n".encode())
        data, err = read_all(s, 30)
        took = time.monotonic() - start
        print(f"normal request {k}: {took*1000:.1f} ms, status line {first(data)!r}, err {err}, tricklers open {len(socks)}")
        time.sleep(1.0)
    stop = True
elif what == "incomplete":
    s = connect()
    start = time.monotonic()
    s.sendall(f"POST /api/v1/jobs?kind=pack HTTP/1.1\r\nHost: {host}\r\nContent-Type: application/toml\r\nContent-Length: 100\r\n\r\nseed = 1\n".encode())
    data, err = read_all(s, float(sys.argv[3]) if len(sys.argv) > 3 else 120)
    took = time.monotonic() - start
    print(f"incomplete body: closed after {took:.2f} s, reply {data[:200]!r}, err {err}")
elif what == "oversize":
    s = connect()
    start = time.monotonic()
    s.sendall(f"POST /api/v1/jobs?kind=pack HTTP/1.1\r\nHost: {host}\r\nContent-Type: application/toml\r\nContent-Length: {(1<<20)+1}\r\n\r\nabc".encode())
    data, err = read_all(s, float(sys.argv[3]) if len(sys.argv) > 3 else 30)
    took = time.monotonic() - start
    print(f"oversize declared, 3 bytes sent: {took:.2f} s, reply {first(data)!r}, {len(data)} bytes, err {err}")
elif what == "slowheaders":
    s = connect()
    start = time.monotonic()
    s.sendall(f"GET /healthz HTTP/1.1\r\nHost: {host}\r\n".encode())
    data, err = read_all(s, 120)
    print(f"headers never finished: closed after {time.monotonic()-start:.2f} s, reply {data[:100]!r}, err {err}")
