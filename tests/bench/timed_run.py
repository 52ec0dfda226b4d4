"""Runs a command and measures it: wall time, and the CPU time (user + system,
all threads) of the process and of every process it waited for (`wait4`), which
depends less than the wall time on other jobs sharing the machine."""
import os
import subprocess
import sys
import time


def timed_run(cmd):
    """(stderr, wall seconds, CPU seconds) of cmd; exits with its stderr if it fails."""
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    err = p.stderr.read()
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(err.strip())
    return err, wall, ru.ru_utime + ru.ru_stime
