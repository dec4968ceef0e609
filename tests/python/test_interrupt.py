# Ctrl-C during a render raises KeyboardInterrupt within a second of the signal (docs/guide/python.md): a child
# process renders a long render, the test sends it SIGINT.
import os
import selectors
import signal
import subprocess
import sys
import textwrap
import time

# The child prints "ready" once the kernel is compiled (the driver's compilation is not
# interruptible; it happens in the constructor), then renders far more samples than the
# test waits for, and reports when the KeyboardInterrupt reached it on the system-wide
# monotonic clock (CLOCK_MONOTONIC, the same in both processes).
CHILD = textwrap.dedent("""
    import sys, time
    import penumbra
    r = penumbra.Renderer(sys.argv[1], width=64, height=64)
    r.render(spp=1)
    print("ready", flush=True)
    try:
        r.render(spp=1000000)
        print("finished", flush=True)
    except KeyboardInterrupt:
        print("interrupted", time.monotonic(), flush=True)
        r.render(spp=1)  # the Renderer still renders after an interrupt
        print("usable", flush=True)
""")

# Expected latency: the waiting thread runs Python's signal handlers every 50 ms
# (python/src/interruptible.h), then the render stops at its next submission, each sized
# to take about 0.25 s (render/pass_bands.h): about 0.3 s. The bound is the contract's one
# second, three times that, for a machine busy with other work.
BOUND_SECONDS = 1.0


def line_within(stream, seconds):
    """The child's next line, or "" when none comes within `seconds` (a child that ignores
    the signal must fail the test, not hang it)."""
    with selectors.DefaultSelector() as selector:
        selector.register(stream, selectors.EVENT_READ)
        return stream.readline() if selector.select(timeout=seconds) else ""


def test_sigint_raises_keyboard_interrupt_within_a_second(cornell):
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(cornell)], stdout=subprocess.PIPE, text=True,
                             env=os.environ.copy())
    try:
        assert line_within(child.stdout, 300).strip() == "ready"
        time.sleep(0.5)  # well inside the long render
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        words = line_within(child.stdout, 10 * BOUND_SECONDS).split()
        assert words and words[0] == "interrupted", words
        latency = float(words[1]) - sent
        assert 0 <= latency < BOUND_SECONDS, latency
        rest, _ = child.communicate(timeout=300)  # what readline buffered included
        assert rest.split() == ["usable"] and child.returncode == 0, rest
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
