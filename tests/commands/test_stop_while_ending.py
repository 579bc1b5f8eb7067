"""A second Ctrl-C (or a SIGTERM) that lands while a stopped command's process ends is ignored.

``test_interrupts``' two-worker run sent its second SIGINT 0.3 s after the first and once saw the
process die of it (exit -2): the command had written ``interrupted`` and returned 130, and the
signal arrived while the interpreter shut down, with SIGINT's handler raising again. In a process
run by :func:`dh2urdf.stop_signals.run_process` (``python -m kin``, the console scripts), the
stop signals are ignored once the command has stopped or returned.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

_CASES = {
    # The command body stops on a Ctrl-C, then the same and a SIGTERM come while it ends.
    "stopped": """
        import os, signal, time
        from dh2urdf.command_line import run_guarded
        from dh2urdf.stop_signals import run_process

        def body():
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(30)
            return 0

        def command():
            code = run_guarded("probe", body)
            os.kill(os.getpid(), signal.SIGINT)
            os.kill(os.getpid(), signal.SIGTERM)
            return code

        code = run_process(command)
        os.kill(os.getpid(), signal.SIGINT)
        print("ended", code, flush=True)
        raise SystemExit(code)
    """,
    # A command that returned: a late Ctrl-C does not turn exit 0 into a traceback.
    "returned": """
        import os, signal
        from dh2urdf.stop_signals import run_process

        code = run_process(lambda: 0)
        os.kill(os.getpid(), signal.SIGINT)
        os.kill(os.getpid(), signal.SIGTERM)
        print("ended", code, flush=True)
        raise SystemExit(code)
    """,
}


@pytest.mark.parametrize(("case", "code"), [("stopped", 130), ("returned", 0)])
def test_a_stop_signal_while_the_process_ends_is_ignored(case, code):
    done = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(_CASES[case])],
        capture_output=True,
        text=True,
        timeout=120,  # a hang guard only
    )
    assert done.returncode == code, (done.returncode, done.stderr)
    assert done.stdout == f"ended {code}\n"
    assert "Traceback" not in done.stderr, done.stderr
    assert done.stderr == ("probe: interrupted\n" if case == "stopped" else ""), done.stderr


def test_an_in_process_command_leaves_the_signals_to_its_caller():
    """Called in-process (not under run_process), a stopped command blocks nothing."""
    script = textwrap.dedent(
        """
        import os, signal, time
        from dh2urdf.command_line import run_guarded

        def body():
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(30)
            return 0

        print(run_guarded("probe", body), flush=True)
        try:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(30)
        except KeyboardInterrupt:
            print("caller's", flush=True)
        """
    )
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120
    )
    assert done.stdout == "130\ncaller's\n", (done.stdout, done.stderr)


def test_a_sigterm_whose_raise_was_swallowed_is_raised_again():
    """A SIGTERM's KeyboardInterrupt raised inside a GC callback is printed and dropped; the
    loops that wait for a cluster's chunks raise it again (raise_lost_stop)."""
    script = textwrap.dedent(
        """
        import gc, os, signal, time
        from dh2urdf.stop_signals import listen_to_stops, raise_lost_stop, terminated

        listen_to_stops()
        fired = []

        def callback(phase, info):  # a SIGTERM lands while the collector runs it
            if phase == "start" and not fired:
                fired.append(1)
                os.kill(os.getpid(), signal.SIGTERM)
                time.sleep(0.5)

        gc.callbacks.append(callback)
        gc.collect()
        gc.callbacks.remove(callback)
        print("ran on", terminated(), flush=True)
        try:
            raise_lost_stop()
        except KeyboardInterrupt:
            print("raised again", flush=True)
        """
    )
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120
    )
    assert done.stdout == "ran on True\nraised again\n", (done.stdout, done.stderr)
    assert "Exception ignored" in done.stderr, done.stderr
