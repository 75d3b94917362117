"""``--tls`` (a generated self-signed certificate), ``--ws-compression`` and the serve
command's options."""

from __future__ import annotations

import argparse
import asyncio
import hashlib
import ssl
import urllib.request
from pathlib import Path

import pytest
from cryptography import x509
from cryptography.hazmat.primitives.serialization import Encoding
from websockets.asyncio.client import connect

from tests.server.harness import running_server
from workcell.cli import serve
from workcell.errors import ConfigError
from workcell.protocol import messages as m
from workcell.protocol.codec import decode_server, encode
from workcell.server.tls import self_signed


def test_certificate_is_generated_once_and_fingerprinted(tmp_path: Path) -> None:
    first = self_signed(tmp_path / "tls", "127.0.0.1")
    cert = x509.load_pem_x509_certificate(first.cert_file.read_bytes())
    digest = hashlib.sha256(cert.public_bytes(Encoding.DER)).hexdigest().upper()
    assert first.fingerprint.replace(":", "") == digest
    assert (first.key_file.stat().st_mode & 0o077) == 0
    assert self_signed(tmp_path / "tls", "127.0.0.1").fingerprint == first.fingerprint
    other = self_signed(tmp_path / "tls", "192.168.77.5")  # another host: a new certificate
    assert other.fingerprint != first.fingerprint


def test_https_and_wss(tmp_path: Path) -> None:
    cert = self_signed(tmp_path / "tls", "127.0.0.1")
    context = ssl.create_default_context(cafile=str(cert.cert_file))
    with running_server(tmp_path, tls=cert) as server:
        url = f"https://127.0.0.1:{server.port}/api/defaults"
        with urllib.request.urlopen(url, context=context, timeout=10) as response:
            assert response.status == 200

        async def wss() -> None:
            uri = f"wss://127.0.0.1:{server.port}/ws"
            async with connect(uri, subprotocols=[m.SUBPROTOCOL], ssl=context) as ws:  # type: ignore[list-item]
                await ws.send(encode(m.Hello(role="spectator")))
                assert isinstance(decode_server(await ws.recv()), m.Welcome)
            await asyncio.sleep(0.2)  # let the close handshake finish before the server stops

        asyncio.run(wss())


def parse(*argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    serve.register(parser.add_subparsers())
    return parser.parse_args(["serve", *argv])


def test_serve_options() -> None:
    options, generated = serve.options_from(parse())
    assert options.host == "127.0.0.1" and options.token is None and not generated
    assert options.store == Path("workcell.sqlite") and options.grace_s == 10.0
    assert not options.ws_compression
    assert serve.options_from(parse("--ws-compression"))[0].ws_compression
    options, generated = serve.options_from(parse("--host", "0.0.0.0", "--tls"))
    assert generated and options.token is not None and len(options.token) >= 16 and options.tls
    options, generated = serve.options_from(parse("--host", "0.0.0.0", "--token", "x" * 12))
    assert not generated and options.token == "x" * 12
    options, _ = serve.options_from(parse("--store", "a.sqlite", "--port", "9", "--grace", "2"))
    assert (options.store, options.port, options.grace_s) == (Path("a.sqlite"), 9, 2.0)
    with pytest.raises(ConfigError) as bad:
        serve.options_from(parse("--port", "70000", "--grace", "-1", "--token", "short"))
    assert len(bad.value.problems) == 3
    options, _ = serve.options_from(
        parse("--allow-origin", "http://localhost:5173", "--allow-origin", "https://a.example")
    )
    assert options.allow_origins == ("http://localhost:5173", "https://a.example")
    with pytest.raises(ConfigError, match="--allow-origin = 'localhost:5173'"):
        serve.options_from(parse("--allow-origin", "localhost:5173"))


@pytest.mark.parametrize("compression", [False, True])
def test_messages_are_compressed_only_with_ws_compression(
    tmp_path: Path, compression: bool
) -> None:
    """A client offering permessage-deflate (as browsers and ``websockets`` do) gets it
    only from a server run with ``--ws-compression``; messages flow either way."""

    async def scenario(url: str) -> str | None:
        async with connect(url, subprotocols=[m.SUBPROTOCOL]) as ws:  # type: ignore[list-item]
            assert ws.request is not None and ws.response is not None
            assert "permessage-deflate" in ws.request.headers["Sec-WebSocket-Extensions"]
            await ws.send(encode(m.Hello(role="spectator")))
            assert isinstance(decode_server(await ws.recv()), m.Welcome)
            return ws.response.headers.get("Sec-WebSocket-Extensions")

    with running_server(tmp_path, ws_compression=compression) as server:
        accepted = asyncio.run(scenario(server.ws))
    if compression:
        assert accepted is not None and accepted.startswith("permessage-deflate")
    else:
        assert accepted is None
