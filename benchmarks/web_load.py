"""Bounded load on the web server: 1, 4, 16, 64 concurrent clients posting the example photo to 127.0.0.1.

Starts ``pix2pockets serve`` on a free port of 127.0.0.1 (or uses ``--url``, which must be a loopback address),
then, level by level, runs N client threads for ``--seconds`` each: every client posts the bundled example photo
to ``POST /api/suggest`` and waits for the answer, again and again; a client refused with 503 waits what
``Retry-After`` says, as a polite client does. Per level it prints throughput (answers per second), latency of
the answered requests (p50 / p95 / max), errors (any answer but 200 and 503, or a broken connection), refusals
(503) and how fast they came, the server's memory (resident set of the server and its workers, sampled every
0.2 s), the server's CPU seconds per answer (which other jobs on the machine do not inflate) and the load average.
After the last level one more request measures how soon the server answers again.

Usage:
    python benchmarks/web_load.py --json web-load.json [--levels 1,4,16,64] [--seconds 30] [--workers 2]
"""

from __future__ import annotations

import argparse
import http.client
import ipaddress
import json
import math
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path
from urllib.parse import urlsplit

BOUNDARY = "p2ploadboundary"


def multipart(photo: bytes, name: str, group: str) -> bytes:
    """The multipart body of one upload."""
    head = (
        f'--{BOUNDARY}\r\nContent-Disposition: form-data; name="group"\r\n\r\n{group}\r\n'
        f'--{BOUNDARY}\r\nContent-Disposition: form-data; name="file"; filename="{name}"\r\n'
        "Content-Type: image/jpeg\r\n\r\n"
    )
    return head.encode() + photo + f"\r\n--{BOUNDARY}--\r\n".encode()


def loopback(url: str) -> tuple[str, int]:
    """(host, port) of ``url``; refuses anything but a loopback address."""
    parts = urlsplit(url)
    host = parts.hostname or ""
    try:
        ok = host == "localhost" or ipaddress.ip_address(host).is_loopback
    except ValueError:
        ok = False
    if not ok or parts.scheme != "http":
        raise SystemExit(f"--url must be http:// on a loopback address (127.0.0.1), got {url!r}")
    return host, parts.port or 80


def tree(pid: int) -> list[int]:
    """``pid`` and all its descendants."""
    children: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
                children.setdefault(int(fields[1]), []).append(int(entry.name))
            except (OSError, IndexError, ValueError):
                continue
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        out.append(p)
        todo.extend(children.get(p, []))
    return out


def tree_rss_mb(pid: int) -> float:
    """Resident memory of ``pid`` and all its descendants [MB]."""
    total = 0
    for p in tree(pid):
        try:
            for line in Path(f"/proc/{p}/status").read_text().splitlines():
                if line.startswith("VmRSS:"):
                    total += int(line.split()[1])
        except OSError:
            pass
    return total / 1024


def tree_cpu_s(pid: int | None) -> float | None:
    """CPU seconds (user + system) used so far by ``pid`` and its live descendants."""
    if not pid:
        return None
    ticks = os.sysconf("SC_CLK_TCK")
    total = 0.0
    for p in tree(pid):
        try:
            fields = Path(f"/proc/{p}/stat").read_text().rsplit(")", 1)[1].split()
            total += (int(fields[11]) + int(fields[12])) / ticks
        except (OSError, IndexError, ValueError):
            pass
    return total


class MemorySampler(threading.Thread):
    """Samples the server's resident memory every 0.2 s; ``take()`` gives the peak since the last take."""

    def __init__(self, pid: int | None) -> None:
        super().__init__(daemon=True)
        self.pid = pid
        self.peak = 0.0
        self.stop = threading.Event()

    def run(self) -> None:
        while self.pid and not self.stop.wait(0.2):
            self.peak = max(self.peak, tree_rss_mb(self.pid))

    def take(self) -> float | None:
        if not self.pid:
            return None
        peak, self.peak = max(self.peak, tree_rss_mb(self.pid)), 0.0
        return round(peak, 1)


def post(conn: http.client.HTTPConnection, body: bytes) -> tuple[int, float, int]:
    """One upload: (status, seconds, Retry-After or 0). The answer is read, not parsed."""
    t = time.perf_counter()
    conn.request("POST", "/api/suggest", body, {"Content-Type": f"multipart/form-data; boundary={BOUNDARY}"})
    response = conn.getresponse()
    response.read()
    retry = response.getheader("Retry-After") or "0"
    return response.status, time.perf_counter() - t, int(retry) if retry.isdigit() else 0


def client(host: str, port: int, body: bytes, end: float, out: list, lock: threading.Lock) -> None:
    """Post until ``end``; record (status, seconds, finished at) per request (status 0: connection error)."""
    conn = http.client.HTTPConnection(host, port, timeout=300)
    while time.monotonic() < end:
        try:
            status, seconds, retry = post(conn, body)
        except (OSError, http.client.HTTPException):
            conn.close()
            conn = http.client.HTTPConnection(host, port, timeout=300)
            with lock:
                out.append((0, 0.0, time.monotonic()))
            time.sleep(0.1)
            continue
        with lock:
            out.append((status, seconds, time.monotonic()))
        if status == 503:
            time.sleep(min(max(retry, 1), max(0.0, end - time.monotonic())))
    conn.close()


def percentile(values: list[float], q: float) -> float | None:
    if not values:
        return None
    values = sorted(values)
    return values[min(len(values) - 1, max(0, math.ceil(q * len(values)) - 1))]


def run_level(host: str, port: int, body: bytes, clients: int, seconds: float, memory: MemorySampler) -> dict:
    out: list = []
    lock = threading.Lock()
    start = time.monotonic()
    end = start + seconds
    memory.take()
    cpu0 = tree_cpu_s(memory.pid)
    threads = [threading.Thread(target=client, args=(host, port, body, end, out, lock)) for _ in range(clients)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    span = max(time.monotonic() - start, seconds)
    cpu1 = tree_cpu_s(memory.pid)
    load = os.getloadavg()[0]
    ok = [s for status, s, _ in out if status == 200]
    refused = [s for status, s, _ in out if status == 503]
    errors = [status for status, _, _ in out if status not in (200, 503)]
    row = {
        "clients": clients,
        "seconds": round(span, 1),
        "answered": len(ok),
        "throughput_per_s": round(len(ok) / span, 3),
        "p50_s": _round(percentile(ok, 0.5)),
        "p95_s": _round(percentile(ok, 0.95)),
        "max_s": _round(max(ok) if ok else None),
        "errors": len(errors),
        "error_statuses": sorted(set(errors)),
        "refused": len(refused),
        "refusal_p95_s": _round(percentile(refused, 0.95)),
        "refusal_max_s": _round(max(refused) if refused else None),
        "server_peak_rss_mb": memory.take(),
        "server_cpu_s_per_answer": _round((cpu1 - cpu0) / len(ok)) if ok and cpu0 is not None else None,
        "load_average_1min": round(load, 2),
    }
    return row


def _round(x: float | None) -> float | None:
    return None if x is None else round(x, 3)


def health(host: str, port: int) -> dict:
    conn = http.client.HTTPConnection(host, port, timeout=10)
    try:
        conn.request("GET", "/api/health")
        return json.loads(conn.getresponse().read())
    finally:
        conn.close()


def wait_idle(host: str, port: int, timeout: float = 300.0) -> None:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        doc = health(host, port)
        if doc.get("running", 0) == 0 and doc.get("queued", 0) == 0:
            return
        time.sleep(0.2)


def first_answer(host: str, port: int, body: bytes) -> float:
    """Seconds until one new request gets its answer (retrying at once on 503)."""
    t = time.perf_counter()
    conn = http.client.HTTPConnection(host, port, timeout=300)
    try:
        while True:
            status, _, _ = post(conn, body)
            if status == 200:
                return time.perf_counter() - t
            time.sleep(0.05)
    finally:
        conn.close()


def start_server(args: argparse.Namespace) -> tuple[subprocess.Popen, int]:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    cmd = [sys.executable, "-m", "pix2pockets.cli.main", "serve", "--host", "127.0.0.1", "--port", str(port)]
    if args.workers is not None:
        cmd += ["--workers", str(args.workers)]
    if args.queue is not None:
        cmd += ["--queue", str(args.queue)]
    log = open(args.server_log, "w") if args.server_log else subprocess.DEVNULL  # noqa: SIM115
    server = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT)
    end = time.monotonic() + 600
    while True:
        if server.poll() is not None:
            raise SystemExit(f"the server exited with code {server.returncode} (see --server-log)")
        try:
            health("127.0.0.1", port)
            return server, port
        except OSError:
            if time.monotonic() > end:
                server.kill()
                raise SystemExit("the server did not start within 600 s") from None
            time.sleep(0.25)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", default="1,4,16,64", help="concurrent clients per level (default 1,4,16,64)")
    parser.add_argument("--seconds", type=float, default=30.0, help="length of each level [s] (default 30)")
    parser.add_argument("--workers", type=int, default=None, help="server workers (default: the server's own)")
    parser.add_argument("--queue", type=int, default=None, help="server queue (default: the server's own)")
    parser.add_argument("--group", default="auto")
    parser.add_argument("--url", help="an already running server on 127.0.0.1 (default: start one)")
    parser.add_argument("--server-pid", type=int, help="with --url: the server's pid, for its memory")
    parser.add_argument("--server-log", help="write the started server's output here")
    parser.add_argument("--json", help="write the results here")
    args = parser.parse_args(argv)
    levels = [int(n) for n in args.levels.split(",")]

    from pix2pockets.data.examples import example_photo_path

    photo = Path(example_photo_path())
    body = multipart(photo.read_bytes(), photo.name, args.group)
    server = None
    if args.url:
        host, port = loopback(args.url)
        pid = args.server_pid
    else:
        server, port = start_server(args)
        host, pid = "127.0.0.1", server.pid
    memory = MemorySampler(pid)
    memory.start()
    try:
        info = health(host, port)
        idle_mb = memory.take()
        rows = []
        print(f"server: {info.get('workers')} workers, queue {info.get('queue')}; idle {idle_mb} MB")
        print(
            f"{'clients':>7} {'answers/s':>9} {'p50 s':>6} {'p95 s':>6} {'max s':>6} {'errors':>6} "
            f"{'refused':>7} {'refusal p95/max s':>17} {'peak MB':>8} {'CPU s/answer':>12} {'load':>5}"
        )
        for clients in levels:
            wait_idle(host, port)
            row = run_level(host, port, body, clients, args.seconds, memory)
            rows.append(row)
            print(
                f"{clients:>7} {row['throughput_per_s']:>9.2f} {_fmt(row['p50_s'])} {_fmt(row['p95_s'])} "
                f"{_fmt(row['max_s'])} {row['errors']:>6} {row['refused']:>7} "
                f"{_fmt(row['refusal_p95_s'], 8)}/{_fmt(row['refusal_max_s'], 8)} "
                f"{_fmt(row['server_peak_rss_mb'], 8, 0)} {_fmt(row['server_cpu_s_per_answer'], 12)} "
                f"{row['load_average_1min']:>5.1f}",
                flush=True,
            )
        recovery = first_answer(host, port, body)  # right after the last level: the queue may still drain
        wait_idle(host, port)
        after = first_answer(host, port, body)
        single = rows[0]["p50_s"] if rows and rows[0]["clients"] == 1 else None
        workers = info.get("workers") or 1
        for row in rows:
            if single:
                row["vs_workers_x_single"] = round(row["throughput_per_s"] / (workers / single), 3)
        print(f"after the last level: first answer in {recovery:.2f} s; once idle, one request takes {after:.2f} s")
        out = {
            "image": f"{photo.name} ({len(body)} bytes posted)",
            "server": {k: info.get(k) for k in ("workers", "queue", "version")},
            "cores": os.cpu_count(),
            "load_average_at_end": list(os.getloadavg()),
            "idle_rss_mb": idle_mb,
            "levels": rows,
            "recovery_first_answer_s": round(recovery, 3),
            "idle_single_request_s": round(after, 3),
        }
        if args.json:
            Path(args.json).write_text(json.dumps(out, indent=2) + "\n")
    finally:
        memory.stop.set()
        if server is not None:
            server.send_signal(signal.SIGINT)
            try:
                server.wait(60)
            except subprocess.TimeoutExpired:
                server.kill()
    return 0


def _fmt(x: float | None, width: int = 6, digits: int = 2) -> str:
    return f"{'-':>{width}}" if x is None else f"{x:>{width}.{digits}f}"


if __name__ == "__main__":
    sys.exit(main())
