#!/usr/bin/env python3
"""Ctrl+C latency of `motionlod export` (issue 29): the worst time from SIGINT to exit.

Runs each export once to time it, then again N times with SIGINT sent at N moments spread
evenly over that duration (on a pty, as a terminal's Ctrl+C would find it), and prints per
command the worst and median latency from the signal to the process's exit, and whether any
run wrote its output.

  scripts/interrupt-latency.py [--motionlod build/bin/motionlod [--motionlod OTHER]] [--runs 20]

(exit -2: ended by SIGINT; 1: the cancelled error; "outputs written" counts signalled runs only.)
"""
import argparse
import os
import pty
import signal
import statistics
import subprocess
import tempfile
import time

MODELS = "/usr/share/assimp/models"
COMMANDS = [
    ["export", f"{MODELS}/BVH/01_03.bvh", "--plugin", "bundle"],
    ["export", f"{MODELS}/X/BCN_Epileptic.X", "--plugin", "gltf"],
    ["export", f"{MODELS}/X/BCN_Epileptic.X", "--plugin", "bundle"],
]


def run(binary, args, out, delay):
    """Seconds from SIGINT (sent `delay` s after the start) to exit; None when it ended first."""
    master, slave = pty.openpty()
    start = time.monotonic()
    # note: a shell starts a background job with SIGINT ignored, and an ignored signal stays
    # ignored across exec: motionlod would then miss a SIGINT that comes before it installs its
    # handler, and run to the end. The child gets the default disposition, as from a terminal.
    proc = subprocess.Popen([binary, *args, "-o", out], stdin=slave, stdout=slave, stderr=slave,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    os.close(slave)
    sent = None
    while True:
        # drain the pty so the process never blocks on its output
        try:
            os.set_blocking(master, False)
            os.read(master, 65536)
        except (BlockingIOError, OSError):
            pass
        if proc.poll() is not None:
            break
        now = time.monotonic()
        if sent is None and delay is not None and now - start >= delay:
            proc.send_signal(signal.SIGINT)
            sent = time.monotonic()
        time.sleep(0.002)
    end = time.monotonic()
    os.close(master)
    return end - start, (end - sent) if sent is not None else None, proc.returncode


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--motionlod", action="append",
                        help="the binary (default build/bin/motionlod); give two or more to compare them under "
                             "the same load: their runs alternate moment by moment")
    parser.add_argument("--runs", type=int, default=20)
    options = parser.parse_args()
    binaries = options.motionlod or ["build/bin/motionlod"]
    with tempfile.TemporaryDirectory() as folder:
        for args in COMMANDS:
            suffix = ".glb" if "gltf" in args else ".mlodb"
            out = os.path.join(folder, "out" + suffix)
            durations = {}
            for binary in binaries:
                durations[binary], _, rc = run(binary, args, out, None)
                if os.path.exists(out):
                    os.remove(out)
            # the moments: spread over the shortest run, so that every binary is signalled while it works
            duration = min(durations.values())
            results = {binary: ([], 0, set()) for binary in binaries}
            for i in range(options.runs):
                for binary in binaries:
                    latencies, written, exits = results[binary]
                    _, latency, rc = run(binary, args, out, duration * (i + 0.5) / options.runs)
                    if latency is not None:
                        latencies.append(latency)
                        exits.add(rc)
                        if os.path.exists(out):
                            written += 1
                    if os.path.exists(out):
                        os.remove(out)
                    results[binary] = (latencies, written, exits)
            for binary in binaries:
                latencies, written, exits = results[binary]
                worst = max(latencies) if latencies else float("nan")
                median = statistics.median(latencies) if latencies else float("nan")
                print(f"{binary}: motionlod {' '.join(args)} -o OUT: run {durations[binary]:.2f} s; SIGINT at "
                      f"{options.runs} moments: worst {worst:.3f} s, median {median:.3f} s, {len(latencies)} signalled "
                      f"before the end: exits {sorted(exits)}, outputs written {written}", flush=True)


if __name__ == "__main__":
    main()
