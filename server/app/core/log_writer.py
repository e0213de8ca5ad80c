"""Log lines written by a thread of their own, not by the event loop.

uvicorn writes an access line per request, synchronously, from the event
loop: under 50 clients posting jobs that write was 10% of the loop's time
(py-spy), time every other request waited for. Its loggers' handlers move
behind a queue, and a listener thread writes what they wrote.
"""

from __future__ import annotations

import logging
import queue
from collections.abc import Callable
from logging.handlers import QueueHandler, QueueListener

LOGGERS = ("uvicorn.access", "uvicorn.error", "uvicorn")


class _Deferred(QueueHandler):
    def prepare(self, record: logging.LogRecord) -> logging.LogRecord:
        # The record as it is: the listener's handlers format it, and uvicorn's
        # formatters read record.args (QueueHandler would merge them into msg).
        return record


def write_logs_off_the_event_loop() -> Callable[[], None]:
    """Moves each uvicorn logger's handlers behind a queue of its own, written
    by a listener thread; answers what puts them back at shutdown (after
    writing what is left)."""
    moved: list[tuple[logging.Logger, _Deferred, QueueListener]] = []
    for name in LOGGERS:
        logger = logging.getLogger(name)
        handlers = [h for h in logger.handlers if not isinstance(h, QueueHandler)]
        if not handlers:
            continue
        lines: queue.SimpleQueue = queue.SimpleQueue()
        deferred = _Deferred(lines)
        for handler in handlers:
            logger.removeHandler(handler)
        logger.addHandler(deferred)
        listener = QueueListener(lines, *handlers, respect_handler_level=True)
        listener.start()
        moved.append((logger, deferred, listener))

    def put_back() -> None:
        for logger, deferred, listener in moved:
            listener.stop()
            logger.removeHandler(deferred)
            for handler in listener.handlers:
                logger.addHandler(handler)
    return put_back
