"""Running scw: a command echoed with its log, the sweep command lines (threads, or worker processes
for the Ipopt-based controllers), a sweep reused when its recorded command is the same, CPU and
wall time, an edited vehicle file."""

import os
import resource
import subprocess
import sys
import time

from scwexp.paths import ROOT


def run(cmd, log=None, check=True):
    """Runs a command (list), echoing it; returns the CompletedProcess. stdout/stderr go to `log`
    (a path) when given, else through."""
    print("+ " + " ".join(cmd), flush=True)
    if log:
        with open(log, "w") as f:
            proc = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT, cwd=ROOT)
    else:
        proc = subprocess.run(cmd, cwd=ROOT)
    if check and proc.returncode != 0:
        extra = f" (log: {log})" if log else ""
        if log:
            with open(log) as f:
                sys.stderr.write(f.read()[-3000:])
        sys.exit(f"error: command failed with exit code {proc.returncode}{extra}")
    return proc


def list_controllers(scw):
    """Motion controllers the binary knows (scw sweep --list-controllers)."""
    out = subprocess.run([scw, "sweep", "--list-controllers"], capture_output=True, text=True,
                         cwd=ROOT)
    if out.returncode != 0:
        return ["pure_pursuit"]
    return [line.strip() for line in out.stdout.splitlines() if line.strip()]


def threads_arg(args):
    return ["--threads", str(args.threads)]


class Timer:
    """Wall time, and the CPU time of the finished child processes (scw and its workers) since
    the start: the wall time depends on what else the machine runs, the CPU time much less."""

    def __init__(self):
        self.t0 = time.monotonic()
        self.c0 = self._children_cpu()

    @staticmethod
    def _children_cpu():
        r = resource.getrusage(resource.RUSAGE_CHILDREN)
        return r.ru_utime + r.ru_stime

    def seconds(self):
        return time.monotonic() - self.t0

    def cpu_seconds(self):
        return self._children_cpu() - self.c0


def sweep_cmd(scw, args, sets, vary, configs, out_csv, extra=()):
    """The scw sweep command line (stop at the first abort as the paper does)."""
    cmd = [scw, "sweep", "--stop-at-first-abort", "-o", out_csv] + threads_arg(args)
    if sets:
        cmd += ["--set"] + list(sets)
    for v in vary:
        cmd += ["--vary", v]
    for c in configs:
        cmd += ["--config", c]
    if getattr(args, "stability", None):
        cmd += ["--stability", args.stability]
    return cmd + list(extra)


def mpc_sweep_cmd(scw, args, sets, vary, configs, out_csv, processes=None, extra=()):
    """sweep_cmd for the Ipopt-based motion controllers (pmpc, nmpc): the runs go to worker
    processes (`scw sweep --processes N`), since their Ipopt calls are serialised within one
    process and threads do not help. The table is the same as with sweep_cmd. processes: the
    number of workers (default: --threads, 0 meaning all cores)."""
    if processes is None:
        processes = getattr(args, "threads", 0) or os.cpu_count() or 1
    cmd = sweep_cmd(scw, args, sets, vary, configs, out_csv, extra)
    i = cmd.index("--threads")
    cmd[i:i + 2] = ["--processes", str(max(1, int(processes)))]
    return cmd


REUSED = []  # tables reuse_or_run read from an earlier run instead of running


def reuse_or_run(cmd, csv_path, log, reuse=False):
    """Runs a sweep writing csv_path, and records its command beside the table
    (csv_path + ".cmd"). With reuse, a table whose recorded command equals this one (the binary
    path aside) is read as it is, without running: sweeps of an interrupted or earlier run with
    the same settings are not repeated."""
    key = "\n".join(cmd[1:])
    side = csv_path + ".cmd"
    if reuse and os.path.exists(csv_path) and os.path.exists(side):
        with open(side) as f:
            if f.read() == key:
                print(f"reusing {os.path.relpath(csv_path, ROOT)} (same command)", flush=True)
                REUSED.append(csv_path)
                return True
    for path in (csv_path, side):
        if os.path.exists(path):
            os.remove(path)
    run(cmd, log=log)
    with open(side, "w") as f:
        f.write(key)
    return False


def brake_40ms_vehicle(scw, path):
    """The built-in vehicle with a 40 ms brake response (brakes.delay 0.006 s: dead time 6 ms +
    the unchanged 32 ms lag and 1800 bar/s rate limit; docs/plant-calibration.md)."""
    run([scw, "vehicle", "init", "-o", path], log=path + ".log")
    with open(path) as f:
        text = f.read()
    lines, in_brakes, done = text.splitlines(), False, False
    for i, line in enumerate(lines):
        if not line.startswith(" "):
            in_brakes = line.startswith("brakes:")
        elif in_brakes and line.strip().startswith("delay:"):
            lines[i] = line[:len(line) - len(line.lstrip())] + "delay: 0.006"
            done = True
    if not done:
        sys.exit(f"error: no brakes.delay in {path}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


