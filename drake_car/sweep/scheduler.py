"""A Dask scheduler's address checked before Dask's Client is made: its form at once, then
its handshake under a timeout (a silent listener or an HTTP server kept the Client
waiting forever; ``foo://`` gave a 20 s stall and a stray traceback)."""

import asyncio
import re

from drake_car.law.checks import one_line

CONNECT_TIMEOUT_S = 10
SCHEDULER_ADDRESS = re.compile(r"^(tcp|tls)://[^/:\s]+:[0-9]{1,5}$")


def check_scheduler(address, timeout_s=None):
    """Refuses, before Dask's Client sees it, an address that is not ``tcp://HOST:PORT`` (or
    tls://) with ValueError, and one where no Dask scheduler answers its handshake (an
    ``identity`` request) within ``timeout_s`` (default CONNECT_TIMEOUT_S) with OSError: a
    silent listener or an HTTP server would otherwise keep the Client waiting forever."""
    from distributed.comm import connect
    if not SCHEDULER_ADDRESS.match(address):
        raise ValueError("not a Dask scheduler address; give tcp://HOST:PORT")
    timeout_s = CONNECT_TIMEOUT_S if timeout_s is None else timeout_s

    async def identity():
        comm = await asyncio.wait_for(connect(address, timeout=timeout_s), timeout_s)
        try:
            await asyncio.wait_for(comm.write({"op": "identity", "reply": True}), timeout_s)
            return await asyncio.wait_for(comm.read(), timeout_s)
        finally:
            comm.abort()
    try:
        reply = asyncio.run(identity())
    except (asyncio.TimeoutError, TimeoutError):
        raise OSError(f"no Dask scheduler answered within {timeout_s:g} s") from None
    except Exception as e:  # closed, refused, not Dask's protocol
        raise OSError(f"no Dask scheduler there ({one_line(e) or type(e).__name__})") from None
    if not (isinstance(reply, dict) and reply.get("type") == "Scheduler"):
        raise OSError("what answered is not a Dask scheduler")
