"""Ctrl-C around native callbacks is taken at the next checkpoint, never lost (strainwave.interrupt)."""
from __future__ import annotations

import os
import signal
import weakref

import pytest

from strainwave.interrupt import deferred_interrupt


class _Held:
    pass


def test_sigint_inside_a_weakref_callback_is_raised_at_the_next_checkpoint():
    reached_checkpoint = False
    with pytest.raises(KeyboardInterrupt):
        with deferred_interrupt() as checkpoint:
            held = _Held()
            # the callback runs where Python would otherwise print "Exception ignored" and go on
            weakref.finalize(held, os.kill, os.getpid(), signal.SIGINT)
            del held
            reached_checkpoint = True
            checkpoint()
    assert reached_checkpoint
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_leaving_the_block_is_a_checkpoint_and_no_signal_changes_nothing():
    with deferred_interrupt() as checkpoint:
        checkpoint()   # nothing received: no exception
    with pytest.raises(KeyboardInterrupt):
        with deferred_interrupt():
            os.kill(os.getpid(), signal.SIGINT)
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_an_ignored_sigint_stays_ignored():
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with deferred_interrupt() as checkpoint:
            os.kill(os.getpid(), signal.SIGINT)
            checkpoint()
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, previous)
