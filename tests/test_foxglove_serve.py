"""docs/foxglove/serve.py: Foxglove's remote-file source opens a recording only from a server
that says `Accept-Ranges: bytes` and answers a range with exactly that slice."""

from __future__ import annotations

import functools
import importlib.util
import threading
import urllib.error
import urllib.request
from http.server import ThreadingHTTPServer
from pathlib import Path

import pytest

from tests.conftest import REPO

_SPEC = importlib.util.spec_from_file_location("serve", REPO / "docs" / "foxglove" / "serve.py")
serve = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(serve)


def test_a_range_comes_back_as_that_slice_and_the_whole_file_says_it_takes_ranges(tmp_path: Path) -> None:
    (tmp_path / "run.mcap").write_bytes(bytes(range(256)) * 4)
    server = ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(serve.RangeHandler, directory=str(tmp_path)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    url = f"http://127.0.0.1:{server.server_address[1]}/run.mcap"
    try:
        with urllib.request.urlopen(url) as whole:
            assert whole.headers["Accept-Ranges"] == "bytes" and whole.headers["Content-Length"] == "1024"
        with urllib.request.urlopen(urllib.request.Request(url, headers={"Range": "bytes=250-261"})) as part:
            assert part.status == 206 and part.headers["Content-Range"] == "bytes 250-261/1024"
            assert part.read() == bytes([250, 251, 252, 253, 254, 255, 0, 1, 2, 3, 4, 5])
        with urllib.request.urlopen(urllib.request.Request(url, headers={"Range": "bytes=1020-"})) as tail:
            assert tail.read() == bytes([252, 253, 254, 255])
        with pytest.raises(urllib.error.HTTPError) as beyond:
            urllib.request.urlopen(urllib.request.Request(url, headers={"Range": "bytes=2000-2001"}))
        assert beyond.value.code == 416
    finally:
        server.shutdown()
        server.server_close()
