# Signals in the module: Python keeps its own handlers (Ctrl-C is a
# KeyboardInterrupt), and a running simulate() stops on Ctrl-C. Each case runs
# in a child interpreter: a regression fails the test instead of killing pytest.
import os
import subprocess
import sys
import textwrap

CFG = {"geometry": {"kind": "micrograin", "tau0": 0.5, "beta": 1.0, "tile": 40},
       "measure": [{"quantity": "tau_plus", "theta_i_deg": [0, 40], "samples": 20000}]}


def child(code, timeout=120):
    """Runs `code` in a fresh interpreter with this one's module path; returns (exit code, stdout, stderr)."""
    p = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=timeout,
                       env=dict(os.environ))
    return p.returncode, p.stdout, p.stderr


def test_ctrl_c_after_a_write_is_a_keyboard_interrupt(tmp_path):
    # The first write used to install the CLI's handlers for SIGINT and SIGTERM
    # (remove the temporaries, then die): Ctrl-C then killed the interpreter,
    # and a user's own SIGTERM handler was replaced.
    code, out, err = child(f"""
        import mcref, os, signal, time
        got = []
        signal.signal(signal.SIGTERM, lambda s, f: got.append(s))
        mcref.write_tables({str(tmp_path / 'x.h5')!r}, mcref.simulate({CFG!r}, seed=2, threads=1))
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.2)
        print('SIGTERM handled' if got else 'SIGTERM not handled')
        try:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(5)
        except KeyboardInterrupt:
            print('KeyboardInterrupt')
        """)
    assert code == 0, f"exit {code} (signal {-code if code < 0 else 0}): {err}"
    assert out.split() == ["SIGTERM", "handled", "KeyboardInterrupt"], out
    assert sorted(os.listdir(tmp_path)) == ["x.h5"]


def test_ctrl_c_stops_a_running_simulation():
    # 10^5 batches of 40 000 paths: hours on one thread, were Ctrl-C left until
    # the end (as it was: the GIL released, no signal ran). The child's timeout
    # is the failure. After the interrupt the module works, with the same bits
    # as before it, on 1 and 2 threads.
    code, out, err = child(f"""
        import mcref, os, signal, threading, numpy as np
        cfg = {CFG!r}
        small = dict(cfg, run={{"batches": 3}})
        before = mcref.simulate(small, seed=4, threads=1)["tau_plus"]
        threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
        try:
            mcref.simulate(dict(cfg, run={{"batches": 100000}}), seed=1, threads=1)
            print("finished")
        except KeyboardInterrupt:
            print("KeyboardInterrupt")
        after = [mcref.simulate(small, seed=4, threads=n)["tau_plus"] for n in (1, 2)]
        same = all(np.array_equal(t.sum, before.sum) and np.array_equal(t.sum_sq, before.sum_sq) for t in after)
        print("same" if same else "differ")
        """)
    assert code == 0, f"exit {code}: {err}"
    assert out.split() == ["KeyboardInterrupt", "same"], out
