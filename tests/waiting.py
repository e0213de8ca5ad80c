"""Waiting for a process under test: polled until it answers."""

import time

import httpx


def wait_until(check, timeout: float, what: str):
    """`check()`'s first true value, polled while it is false or its server
    does not answer yet; AssertionError naming `what` after `timeout` seconds."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            value = check()
            if value:
                return value
        except (httpx.HTTPError, OSError):
            pass
        time.sleep(0.1)
    raise AssertionError(f"timed out waiting for {what}")
