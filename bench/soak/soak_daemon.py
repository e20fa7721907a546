#!/usr/bin/env python3
"""Soak of spinewatchd (issue 17, docs/performance.md "Soak").

Runs the real daemon on the embedded default (the phantom recording)
replayed with `[cameras] replay = "fast"` until it has taken PAIRS pairs,
while one observer client reads every line over the Unix socket and a
churn of clients connects over TCP and the Unix socket, reads quickly,
slowly or not at all, sends a command now and then, and vanishes at
random (a normal close, a reset, or in the middle of a line).

Recorded over time from /proc/PID: resident memory (VmRSS) and open file
descriptors, with the daemon's own counters from the observer's posture
lines (pairs, pairs_dropped, frames_lost, clients, clients_dropped).
Every CHECKPOINT pairs the churn pauses until only the observer is
connected and the descriptors are counted then ("quiescent"), so clients
in flight do not blur the figure.

Reported: the RSS slope after warm-up in KB per 10^4 pairs (least
squares; target < 1 KB), the quiescent descriptor counts (target: all
equal), the drop counters at warm-up and at the end (target: unchanged),
the observer's sequence gaps, and the daemon's exit status after SIGTERM.
The samples go to OUT.csv, the summary to OUT.json.

    bench/soak/soak_daemon.py --daemon build/release/daemon/spinewatchd \\
        --demo build/release/share/spinewatch/demo --pairs 1000000 --out build/release/soak
"""
import argparse
import asyncio
import json
import os
import random
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import time


def vm_rss_kb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise RuntimeError("no VmRSS")


def fd_count(pid):
    return len(os.listdir(f"/proc/{pid}/fd"))


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def slope_per_1e4(xs, ys):
    n = len(xs)
    if n < 2:
        return float("nan")
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    sxy = sum((x - mx) * (y - my) for x, y in zip(xs, ys))
    return sxy / sxx * 1e4 if sxx else float("nan")


class Observer:
    """Reads every line; keeps the last stats and counts sequence gaps."""

    def __init__(self):
        self.stats = {}
        self.last_seq = None
        self.seq_gaps = 0
        self.lines = 0
        self.dropped = False

    SEQ = re.compile(rb'"class":"posture".*?"seq":(\d+)')

    async def run(self, path):
        # A large receive buffer, and a full JSON parse of only every 64th
        # line (the sequence number of every line is taken by a regex): a
        # Python reader must keep up with ~1000 lines/s of 4 KB or the
        # daemon rightly drops it (the first run here was dropped that way).
        s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 8 << 20)
        s.connect(path)
        reader, self.writer = await asyncio.open_unix_connection(sock=s, limit=1 << 22)
        while True:
            line = await reader.readline()
            if not line:
                self.dropped = True  # the daemon closed us: we did not keep up, or it stopped
                return
            if not line.endswith(b"\n"):
                raise RuntimeError("observer: half a line at EOF")
            self.lines += 1
            m = self.SEQ.match(line, 0, 200) or self.SEQ.search(line, 0, 200)
            if not m:
                continue
            seq = int(m.group(1))
            if self.last_seq is not None and seq != self.last_seq + 1:
                self.seq_gaps += 1
            self.last_seq = seq
            if self.lines % 64 == 0:
                self.stats = json.loads(line).get("stats", self.stats)


class Churn:
    """Clients that come and go at random."""

    BEHAVIOURS = ("quick", "slow", "stall", "half_line", "command")

    def __init__(self, tcp, unix_path, concurrency, rng):
        self.tcp, self.unix_path, self.concurrency, self.rng = tcp, unix_path, concurrency, rng
        self.paused = asyncio.Event()
        self.running = 0
        self.started = {b: 0 for b in self.BEHAVIOURS}
        self.refused = 0

    async def connect(self):
        loop = asyncio.get_running_loop()
        if self.rng.random() < 0.5:
            s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
            addr = self.tcp
        else:
            s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            addr = self.unix_path
        s.setblocking(False)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 16384)
        await loop.sock_connect(s, addr)
        return s

    def vanish(self, s):
        # Half the time a reset (SO_LINGER 0) instead of an orderly close.
        if self.rng.random() < 0.5:
            s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
        s.close()

    async def recv_some(self, s, n, timeout):
        loop = asyncio.get_running_loop()
        try:
            return await asyncio.wait_for(loop.sock_recv(s, n), timeout)
        except asyncio.TimeoutError:
            return None

    async def one(self):
        loop = asyncio.get_running_loop()
        behaviour = self.rng.choice(self.BEHAVIOURS)
        self.started[behaviour] += 1
        try:
            s = await self.connect()
        except OSError:
            self.refused += 1
            return
        try:
            if behaviour == "quick":
                for _ in range(self.rng.randint(1, 40)):
                    if not await self.recv_some(s, 65536, 1.0):
                        break
            elif behaviour == "slow":
                until = time.monotonic() + self.rng.uniform(0.5, 6.0)
                while time.monotonic() < until:
                    data = await self.recv_some(s, self.rng.choice((512, 2048, 8192)), 1.0)
                    if data == b"":
                        break  # the daemon dropped us for not keeping up
                    await asyncio.sleep(self.rng.uniform(0.02, 0.3))
            elif behaviour == "stall":
                await asyncio.sleep(self.rng.uniform(0.2, 4.0))
            elif behaviour == "half_line":
                await self.recv_some(s, self.rng.randint(1, 3000), 1.0)
            elif behaviour == "command":
                line = self.rng.choice((b'{"command": "hello"}\n', b"not json\n", b'{"command": "set_worker", "height": 1}\n'))
                await loop.sock_sendall(s, line)
                for _ in range(self.rng.randint(1, 10)):
                    if not await self.recv_some(s, 65536, 1.0):
                        break
        except OSError:
            pass  # reset by the daemon (dropped): part of the game
        finally:
            self.vanish(s)

    async def slot(self):
        while True:
            await self.paused.wait()
            self.running += 1
            try:
                await self.one()
            finally:
                self.running -= 1
            await asyncio.sleep(self.rng.uniform(0.0, 0.2))

    async def quiesce(self):
        self.paused.clear()
        while self.running:
            await asyncio.sleep(0.05)


async def soak(args):
    os.makedirs(os.path.dirname(os.path.abspath(args.out)) or ".", exist_ok=True)
    work = tempfile.mkdtemp(prefix="spinewatch-soak-")
    env = dict(os.environ)
    if args.demo:
        # A private copy of the embedded default: a rebuild during the soak
        # re-renders the build tree's copy under the daemon's feet (the
        # first run here ended that way: "the file shrank").
        shutil.copytree(args.demo, os.path.join(work, "demo"))
        env["SPINEWATCH_DATA_DIR"] = work
    port = free_port()
    unix_path = os.path.join(work, "posture.sock")
    config = os.path.join(work, "spinewatch.toml")
    with open(config, "w") as f:
        f.write(f"""[cameras]
source = "recording"
replay = "fast"
[publish]
listen = "127.0.0.1:{port}"
unix_socket = "{unix_path}"
max_clients = 32
[log]
level = "info"
status_interval_s = 30
""")
    log = open(args.out + ".log", "w")
    daemon = subprocess.Popen([args.daemon, "--config", config], stdout=log, stderr=subprocess.STDOUT, env=env)
    DAEMONS.append(daemon)
    pid = daemon.pid
    for _ in range(200):
        if os.path.exists(unix_path):
            break
        await asyncio.sleep(0.05)
    else:
        raise RuntimeError("the daemon did not open its socket; see " + args.out + ".log")

    observer = Observer()
    observe = asyncio.create_task(observer.run(unix_path))
    rng = random.Random(args.seed)
    churn = Churn(("127.0.0.1", port), unix_path, args.clients, rng)
    slots = [asyncio.create_task(churn.slot()) for _ in range(args.clients)]
    churn.paused.set()

    samples, quiescent = [], []
    csv = open(args.out + ".csv", "w")
    csv.write("t_s,pairs,rss_kb,fds,clients,pairs_dropped,frames_lost,clients_dropped,churn_running\n")
    start = time.monotonic()
    next_checkpoint = args.checkpoint

    def sample():
        st = observer.stats
        row = dict(t_s=round(time.monotonic() - start, 1), pairs=st.get("pairs", 0), rss_kb=vm_rss_kb(pid),
                   fds=fd_count(pid), clients=st.get("clients", 0), pairs_dropped=st.get("pairs_dropped", 0),
                   frames_lost=st.get("frames_lost", 0), clients_dropped=st.get("clients_dropped", 0),
                   churn_running=churn.running)
        samples.append(row)
        csv.write(",".join(str(row[k]) for k in row) + "\n")
        csv.flush()
        return row

    async def checkpoint():
        await churn.quiesce()
        deadline = time.monotonic() + 10
        while observer.stats.get("clients") != 1 and time.monotonic() < deadline:
            await asyncio.sleep(0.1)
        await asyncio.sleep(0.3)
        row = sample()
        quiescent.append(dict(pairs=row["pairs"], fds=row["fds"], clients=row["clients"], rss_kb=row["rss_kb"]))
        print(f"[{row['t_s']:7.0f} s] {row['pairs']:>8} pairs  RSS {row['rss_kb']} KB  fds {row['fds']} "
              f"(quiescent, {row['clients']} client)  pairs_dropped {row['pairs_dropped']}  "
              f"frames_lost {row['frames_lost']}  clients_dropped {row['clients_dropped']}", flush=True)
        churn.paused.set()

    while True:
        await asyncio.sleep(args.interval)
        if observe.done():
            raise RuntimeError("the observer stopped: " + ("dropped by the daemon" if observer.dropped else str(observe.exception())))
        if daemon.poll() is not None:
            raise RuntimeError(f"the daemon exited with {daemon.returncode}")
        row = sample()
        if row["pairs"] >= next_checkpoint or row["pairs"] >= args.pairs:
            await checkpoint()
            next_checkpoint += args.checkpoint
        if row["pairs"] >= args.pairs:
            break
        if args.seconds and time.monotonic() - start >= args.seconds:
            print(f"soak: stopped by --seconds {args.seconds} at {row['pairs']} pairs", flush=True)
            await checkpoint()
            break

    churn.paused.clear()
    for t in slots:
        t.cancel()
    daemon.send_signal(signal.SIGTERM)
    exit_code = daemon.wait(timeout=30)
    try:
        await asyncio.wait_for(observe, 5)
    except Exception:
        pass
    elapsed = time.monotonic() - start

    after = [s for s in samples if s["pairs"] >= args.warmup]
    at_warmup = after[0] if after else samples[-1]
    end = samples[-1]
    summary = dict(
        pairs_target=args.pairs, pairs=end["pairs"], seconds=round(elapsed), pairs_per_s=round(end["pairs"] / elapsed, 1),
        warmup_pairs=args.warmup,
        rss_kb_at_warmup=at_warmup["rss_kb"], rss_kb_end=end["rss_kb"], rss_kb_max=max(s["rss_kb"] for s in samples),
        rss_slope_kb_per_1e4_pairs=round(slope_per_1e4([s["pairs"] for s in after], [s["rss_kb"] for s in after]), 4),
        quiescent_fds=sorted({q["fds"] for q in quiescent}), checkpoints=len(quiescent),
        fds_min=min(s["fds"] for s in samples), fds_max=max(s["fds"] for s in samples),
        pairs_dropped_at_warmup=at_warmup["pairs_dropped"], pairs_dropped_end=end["pairs_dropped"],
        frames_lost_at_warmup=at_warmup["frames_lost"], frames_lost_end=end["frames_lost"],
        clients_dropped_end=end["clients_dropped"], observer_seq_gaps=observer.seq_gaps,
        observer_lines=observer.lines, churn_clients=churn.started, churn_refused=churn.refused,
        daemon_exit=exit_code, samples=len(samples))
    with open(args.out + ".json", "w") as f:
        json.dump(summary, f, indent=1)
    print(json.dumps(summary, indent=1))
    ok = (summary["rss_slope_kb_per_1e4_pairs"] < 1.0 and len(summary["quiescent_fds"]) == 1
          and summary["pairs_dropped_end"] == summary["pairs_dropped_at_warmup"]
          and summary["frames_lost_end"] == summary["frames_lost_at_warmup"] and exit_code == 0)
    print("soak:", "flat" if ok else "NOT FLAT (see above)")
    return 0 if ok else 1


async def soak_and_clean_up(args):
    try:
        return await soak(args)
    finally:
        for proc in DAEMONS:
            if proc.poll() is None:
                proc.kill()  # a failed soak leaves no daemon behind


DAEMONS = []


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--daemon", required=True, help="the spinewatchd to soak")
    p.add_argument("--demo", help="the embedded default recording to copy (<build>/share/spinewatch/demo)")
    p.add_argument("--pairs", type=int, default=1_000_000)
    p.add_argument("--warmup", type=int, default=100_000, help="pairs before the slope is measured")
    p.add_argument("--checkpoint", type=int, default=100_000, help="pairs between quiescent descriptor counts")
    p.add_argument("--clients", type=int, default=6, help="churning clients at a time")
    p.add_argument("--interval", type=float, default=2.0, help="seconds between samples")
    p.add_argument("--seconds", type=float, default=0, help="stop earlier than --pairs after this long (0: no limit)")
    p.add_argument("--seed", type=int, default=17)
    p.add_argument("--out", default="soak", help="prefix of OUT.csv, OUT.json, OUT.log")
    args = p.parse_args()
    sys.exit(asyncio.run(soak_and_clean_up(args)))


if __name__ == "__main__":
    main()
