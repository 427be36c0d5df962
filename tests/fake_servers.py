"""A TCP listener on 127.0.0.1 that greets every connection with some bytes and closes it: a stand-in for a
server at a ``--scheduler`` address that is not a dask scheduler (tests of the probe and of run_cases)."""
from __future__ import annotations

import contextlib
import socket
import threading
import time
from typing import Callable, Iterator, Sequence


@contextlib.contextmanager
def greeting_listener(greeting: Callable[[], bytes | Sequence[bytes]], hold_s: float = 0.0) -> Iterator[str]:
    """Serve ``greeting()`` to every connection (bytes, or a list of byte pieces sent 0.1 s apart), keep it open
    ``hold_s`` seconds, close it; yields the address ``tcp://127.0.0.1:PORT``.  A client that hangs up early is
    not an error."""
    lst = socket.socket()
    lst.bind(("127.0.0.1", 0))
    lst.listen(16)
    lst.settimeout(0.2)
    stop = threading.Event()

    def serve():
        while not stop.is_set():
            try:
                c, _ = lst.accept()
            except OSError:
                continue
            with c:
                try:
                    g = greeting()
                    for k, piece in enumerate(g if isinstance(g, (list, tuple)) else [g]):
                        if k:
                            time.sleep(0.1)  # a greeting in pieces: each arrives in its own read
                        c.sendall(piece)
                    time.sleep(hold_s)
                except OSError:
                    pass

    th = threading.Thread(target=serve, daemon=True)
    th.start()
    try:
        yield f"tcp://127.0.0.1:{lst.getsockname()[1]}"
    finally:
        stop.set()
        th.join(2)
        lst.close()
