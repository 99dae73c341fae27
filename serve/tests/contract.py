#!/usr/bin/env python3
"""The service's contract, checked by tools that did not write it.

Starts `gapack serve` on a loopback port (a token, small ceilings so that
fuzzed jobs finish quickly, a fresh data folder), checks its OpenAPI
document with openapi-spec-validator, then runs schemathesis against the
server with every check, the coverage, fuzzing and stateful phases and a
fixed seed. Prints the figures (operations, test cases generated,
failures) and exits non-zero on any failure. Stops the server at the end.

Usage: contract.py GAPACK_BINARY [--max-examples N] [--seed S] [--reports DIR]
Needs: pip install schemathesis==4.32.5 openapi-spec-validator==0.9.0
"""

import argparse
import json
import os
import queue
import secrets
import shutil
import subprocess
import sys
import tempfile
import threading
import urllib.request
from pathlib import Path

HERE = Path(__file__).resolve().parent
CONFIG = HERE / "schemathesis.toml"
# The server's first stdout line, and how long to wait for it.
LISTENING = "listening on "
START_SECONDS = 60
# The whole schemathesis run's bound (s): a hung request fails the run.
RUN_SECONDS = 900


def start(binary, folder, token):
    """Start the server; return the process and its base URL."""
    token_file = folder / "token"
    token_file.write_text(token + "\n")
    server = subprocess.Popen(
        [
            binary, "serve",
            "--listen", "127.0.0.1:0",
            "--data", str(folder / "data"),
            "--token-file", str(token_file),
            "--workers", "2",
            "--max-particles", "5000",
            "--max-memory-mb", "256",
            "--max-seconds", "3",
            "--max-queue", "100000",
        ],
        stdout=subprocess.PIPE,
        stderr=open(folder / "server.log", "wb"),
        text=True,
    )
    # Its stdout is read to the end (so that it never fills), the first
    # line handed over.
    first = queue.Queue()

    def drain():
        for n, line in enumerate(server.stdout):
            if n == 0:
                first.put(line)
        first.put("")

    threading.Thread(target=drain, daemon=True).start()
    try:
        line = first.get(timeout=START_SECONDS)
    except queue.Empty:
        line = ""
    if not line.startswith(LISTENING):
        server.kill()
        server.wait()
        sys.exit(f"contract: the server did not start: {line!r}; see {folder / 'server.log'}")
    return server, line[len(LISTENING):].strip()


def figures(report):
    """Operations tested, test cases generated, and the unique failures
    (operation, code, title) and errors, from schemathesis' NDJSON events."""
    operations, generated, failures, errors = set(), 0, set(), 0
    for line in report.read_text().splitlines():
        event = json.loads(line)
        body = event.get("ScenarioFinished")
        if body is None:
            continue
        recorder = body.get("recorder", {})
        label = recorder.get("label", "")
        if body.get("phase") != "stateful":
            operations.add(label)
        if body.get("status") == "error":
            errors += 1
        generated += len(recorder.get("cases", {}))
        for checks in recorder.get("checks", {}).values():
            for check in checks:
                if check.get("status") == "failure":
                    failure = check.get("failure_info", {}).get("failure", {})
                    failures.add((failure.get("operation", label), failure.get("code"), failure.get("title")))
    return operations, generated, failures, errors


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("binary", help="the gapack binary (target/debug/gapack)")
    parser.add_argument("--max-examples", type=int, default=100)
    parser.add_argument("--seed", type=int, default=20261206)
    parser.add_argument("--reports", help="keep schemathesis' NDJSON report and the server's log in this folder")
    args = parser.parse_args()
    missing = [t for t in ("schemathesis", "openapi-spec-validator") if shutil.which(t) is None]
    if missing:
        sys.exit(f"contract: {', '.join(missing)} not found: pip install schemathesis==4.32.5 openapi-spec-validator==0.9.0")
    token = secrets.token_hex(16)
    with tempfile.TemporaryDirectory(prefix="gapack-contract-") as tmp:
        folder = Path(tmp)
        server, url = start(os.path.abspath(args.binary), folder, token)
        try:
            request = urllib.request.Request(
                f"{url}/api/v1/openapi.json",
                headers={"Authorization": f"Bearer {token}"},
            )
            with urllib.request.urlopen(request, timeout=30) as r:
                document = folder / "openapi.json"
                document.write_bytes(r.read())
            print("== openapi-spec-validator", flush=True)
            checked = subprocess.run(["openapi-spec-validator", str(document)])
            if checked.returncode != 0:
                sys.exit("contract: the served document is not valid OpenAPI")
            print("== schemathesis", flush=True)
            reports = Path(args.reports).resolve() if args.reports else folder / "reports"
            command = [
                "schemathesis", "--config-file", str(CONFIG), "run",
                "--checks", "all",
                "--phases", "coverage,fuzzing,stateful",
                "--mode", "all",
                "--seed", str(args.seed),
                "--max-examples", str(args.max_examples),
                "--generation-database", "none",
                "--workers", "1",
                "--no-color",
                "--report", "ndjson",
                "--report-dir", str(reports),
                # The document as served (the server asks a token for it too).
                str(document),
                "--url", url,
            ]
            print(" ".join(command), flush=True)
            run = subprocess.run(
                command,
                env={**os.environ, "GAPACK_CONTRACT_TOKEN": token},
                # Its caches go to the temporary folder, not the checkout.
                cwd=folder,
                timeout=RUN_SECONDS,
            )
            ndjson = next(reports.glob("*.ndjson"), None)
            if ndjson is None:
                sys.exit(f"contract: schemathesis wrote no report (exit {run.returncode})")
            operations, generated, failures, errors = figures(ndjson)
            print(
                f"contract: {len(operations)} operations, {generated} test cases generated, "
                f"{len(failures)} unique failures, {errors} errors "
                f"(schemathesis exit {run.returncode})"
            )
            for operation, code, title in sorted(failures, key=str):
                print(f"  failure: {operation}: {code} {title}")
            if run.returncode != 0 or failures or errors:
                log = (folder / "server.log").read_text(errors="replace")
                print("== the server's log (last lines)")
                print("\n".join(log.splitlines()[-20:]))
                return 1
            return 0
        finally:
            server.terminate()
            try:
                server.wait(timeout=30)
            except subprocess.TimeoutExpired:
                server.kill()
                server.wait()
            if args.reports:
                shutil.copy(folder / "server.log", Path(args.reports) / "server.log")


if __name__ == "__main__":
    sys.exit(main())
