"""Who may drive `warpoptics view` (docs/preview_security.md): probes with raw sockets against a
server on a free 127.0.0.1 port.

Every request must name the server in ``Host`` (DNS rebinding sends the attacker's name); a
write must carry a same-origin ``Origin`` (when one is sent), ``Content-Type: application/json``
and the launch's token; malformed bodies (too deep, cut short, too long, not an object, unknown
controls, non-finite numbers) are answered with a 4xx status and leave the preview as it was,
and nothing prints a traceback.
"""

from __future__ import annotations

import json
import socket
import struct

import pytest

import warpoptics as wo
from warpoptics.commands import view
from warpoptics.commands.view import MAX_BODY, ViewServer
from warpoptics.pipelines.preview import Preview

SCENE = {
    "camera": {
        "position": [0.0, -22.0, 30.0],
        "look_at": [0.0, 0.0, -0.3],
        "fov": 15.0,
        "width": 8,
        "height": 6,
    },
    "render": {"spectral": "stratified", "wavelengths": 3, "max_depth": 4},
    "light": [{"type": "environment", "map": "studio"}],
    "object": [{"shape": "round_brilliant", "diameter": 6.5, "material": "diamond"}],
}
TIMEOUT = 120  # seconds per probe (a frame of 8x6 takes milliseconds; a loaded CI machine is slow)


@pytest.fixture
def preview(device):
    return Preview(wo.Scene.from_dict(SCENE), draft_scale=1, device=device)


@pytest.fixture
def server(preview, monkeypatch):
    monkeypatch.setattr(view, "_READ_TIMEOUT", 2.0)  # the stalled-body probe waits this long
    with ViewServer(preview, port=0) as srv:
        yield srv


def request(method: str, path: str, host: str | None, headers=None, body: bytes = b"") -> bytes:
    lines = [f"{method} {path} HTTP/1.1"]
    if host is not None:
        lines.append(f"Host: {host}")
    for k, v in (headers or {}).items():
        lines.append(f"{k}: {v}")
    return ("\r\n".join(lines) + "\r\n\r\n").encode("latin-1") + body


def send(port: int, data: bytes, *, shut: bool = False, reset: bool = False) -> tuple[int | None, bytes]:
    """Send raw bytes, read the answer to the end: (status, body).  ``shut``: close our sending
    side after the data (a client that stops mid-body); ``reset``: abort the connection (RST)
    right after sending, reading nothing (status None)."""
    with socket.create_connection(("127.0.0.1", port), timeout=TIMEOUT) as s:
        s.sendall(data)
        if reset:
            s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
            return None, b""
        if shut:
            s.shutdown(socket.SHUT_WR)
        reply = b""
        while chunk := s.recv(65536):
            reply += chunk
    head, _, body = reply.partition(b"\r\n\r\n")
    return int(head.split(b" ", 2)[1]), body


def post(
    srv, body: bytes, *, token: str | None = "", origin: str | None = None, ctype="application/json", **kw
):
    headers = {"Content-Type": ctype, "Content-Length": str(len(body))}
    if token is not None:
        headers["X-Warpoptics-Token"] = token or srv.token
    if origin is not None:
        headers["Origin"] = origin
    return send(srv.port, request("POST", "/controls", f"127.0.0.1:{srv.port}", headers, body), **kw)


def test_every_request_must_name_this_server(server, capfd):
    port = server.port
    for path in ("/", "/state", "/frame.jpg", "/frame.png", "/nothing"):
        for host in ("evil.example", f"evil.example:{port}", f"127.0.0.1:{port + 1}", "127.0.0.1", None):
            status, body = send(port, request("GET", path, host))
            assert status == 403, (path, host)
            assert b"controls" not in body and b"warpoptics-token" not in body
    for host in (f"127.0.0.1:{port}", f"localhost:{port}", f"LocalHost:{port}", f"[::1]:{port}"):
        assert send(port, request("GET", "/state", host))[0] == 200, host
    # another site's page that names the right host (<img src="http://127.0.0.1:PORT/frame.jpg">):
    # its browser says so, and the request is refused before any pass is rendered
    passes = server.preview.passes
    for site in ("cross-site", "same-site"):
        for path in ("/frame.jpg", "/state", "/"):
            headers = {"Sec-Fetch-Site": site}
            assert send(port, request("GET", path, f"127.0.0.1:{port}", headers))[0] == 403, (site, path)
    assert server.preview.passes == passes
    for site in ("same-origin", "none"):  # the page's own requests; a typed address or a bookmark
        assert send(port, request("GET", "/state", f"127.0.0.1:{port}", {"Sec-Fetch-Site": site}))[0] == 200
    # a rebinding page's POST is refused for its Host, token or not
    body = b'{"azimuth": 90}'
    headers = {"Content-Type": "application/json", "Content-Length": "15", "X-Warpoptics-Token": server.token}
    assert send(port, request("POST", "/controls", f"evil.example:{port}", headers, body))[0] == 403
    assert "Traceback" not in capfd.readouterr().err


def test_writes_need_origin_json_and_token(server, preview, capfd):
    gen = preview.generation
    body = json.dumps({"azimuth": 90.0}).encode()
    port = server.port
    # the curl: another site's no-cors text/plain fetch
    assert post(server, body, token=None, origin="http://evil.example", ctype="text/plain")[0] == 403
    assert post(server, body, origin="http://evil.example")[0] == 403  # even with the token
    assert post(server, body, origin="null")[0] == 403  # a sandboxed frame or a file:// page
    assert post(server, body, origin=f"http://127.0.0.1:{port + 1}")[0] == 403
    assert post(server, body, ctype="text/plain")[0] == 415
    assert post(server, body, ctype="application/x-www-form-urlencoded")[0] == 415
    assert post(server, body, token=None)[0] == 403
    assert post(server, body, token="x" + server.token[1:])[0] == 403
    assert preview.generation == gen  # nothing of the above changed the preview
    # the page's own requests: same origin (by any of the server's names) or none, JSON, token
    status, reply = post(server, body, origin=f"http://127.0.0.1:{port}")
    assert status == 200 and json.loads(reply)["values"]["azimuth"] == 90.0
    assert post(server, json.dumps({"azimuth": 80.0}).encode(), origin=f"http://localhost:{port}")[0] == 200
    assert (
        post(server, json.dumps({"azimuth": 70.0}).encode(), ctype="application/json; charset=utf-8")[0]
        == 200
    )
    assert preview.generation == gen + 3
    # an unknown endpoint with the token is a 404; without it the same 403 as any foreign write
    headers = {"Content-Type": "application/json", "Content-Length": "2", "X-Warpoptics-Token": server.token}
    assert send(port, request("POST", "/other", f"127.0.0.1:{port}", headers, b"{}"))[0] == 404
    assert "Traceback" not in capfd.readouterr().err


def test_the_page_carries_this_launchs_token(preview):
    with ViewServer(preview, port=0) as a, ViewServer(preview, port=0) as b:
        assert a.token != b.token and len(a.token) >= 32
        status, page = send(a.port, request("GET", "/", f"127.0.0.1:{a.port}"))
        assert status == 200
        assert f'<meta name="warpoptics-token" content="{a.token}">'.encode() in page
        assert b"X-Warpoptics-Token" in page and b.token.encode() not in page


@pytest.mark.parametrize(
    "body,status,message",
    [
        (b"[" * 32000 + b"]" * 32000, 400, "nested too deeply"),  # RecursionError in the parser
        (b"{not json", 400, "not valid JSON"),
        (b"\xff\xfe{}", 400, "not valid JSON"),
        (b"[1, 2]", 400, "expected an object"),
        (b"3", 400, "expected an object"),
        (b'"azimuth"', 400, "expected an object"),
        (b'{"nope": 1}', 400, "no such control"),
        (b'{"azimuth": NaN}', 400, "NaN is not a JSON number"),
        (b'{"azimuth": -Infinity}', 400, "-Infinity is not a JSON number"),
        (b'{"azimuth": 1e999}', 400, "beyond the float range"),
        (b'{"azimuth": 1' + b"0" * 400 + b"}", 400, "finite"),
        (b'{"azimuth": true}', 400, "must be a number"),
        (b'{"azimuth": ' + b"[" * 100 + b"]" * 100 + b"}", 400, "must be a number"),
        (b'{"object.0.material": "unobtainium"}', 400, "object.0.material"),
        (b'{"distance": 0}', 400, "out of range"),
    ],
)
def test_malformed_bodies_are_refused(server, preview, capfd, body, status, message):
    gen, values = preview.generation, preview.values()
    got, reply = post(server, body)
    assert got == status
    error = json.loads(reply)["error"]
    assert message in error and "\n" not in error
    assert preview.generation == gen and preview.values() == values
    assert "Traceback" not in capfd.readouterr().err


def test_bodies_too_long_short_or_missing(server, preview, capfd):
    port = server.port
    host = f"127.0.0.1:{port}"
    base = {"Content-Type": "application/json", "X-Warpoptics-Token": server.token}

    def probe(headers, body=b"", **kw):
        return send(port, request("POST", "/controls", host, {**base, **headers}, body), **kw)

    gen = preview.generation
    assert probe({"Content-Length": str(10**12)})[0] == 413  # refused unread
    assert probe({"Content-Length": str(MAX_BODY + 1)}, b"{" * 100)[0] == 413
    assert probe({})[0] == 411
    assert probe({"Transfer-Encoding": "chunked"}, b"2\r\n{}\r\n0\r\n\r\n")[0] == 411
    assert probe({"Content-Length": "ten"})[0] == 400
    assert probe({"Content-Length": "-5"})[0] == 400
    assert probe({"Content-Length": "0"})[0] == 400
    # a client that disconnects mid-body: it stops sending (its answer is a 400) ...
    status, reply = probe({"Content-Length": "1000"}, b'{"azimuth": 1', shut=True)
    assert status == 400 and "ended after 13 of 1000 bytes" in json.loads(reply)["error"]
    # ... or aborts the connection (nobody to answer); or stalls past the read timeout
    probe({"Content-Length": "1000"}, b'{"azimuth": 1', reset=True)
    status, reply = probe({"Content-Length": "100"}, b'{"azimuth"')
    assert status == 408
    # the server still serves, nothing changed, nothing printed a traceback
    assert send(port, request("GET", "/state", host))[0] == 200
    assert preview.generation == gen
    assert "Traceback" not in capfd.readouterr().err


def test_clients_that_vanish_print_nothing(server, capfd):
    """Connections aborted before, inside or after the request line, or half sent and closed,
    or a frame's client gone mid-answer: the terminal stays silent and the server serves on."""
    port = server.port
    host = f"127.0.0.1:{port}"
    send(port, b"", reset=True)
    send(port, b"GET /sta", reset=True)
    send(port, b"GET /state HTTP/1.1\r\nHost: " + host.encode(), reset=True)
    send(port, request("GET", "/frame.jpg", host), reset=True)
    status, _ = send(port, b"GET /state HTTP/1.1\r\nHost: " + host.encode(), shut=True)
    assert status == 200  # the headers end at the close: the request as sent, this server's Host
    assert send(port, request("GET", "/state", host))[0] == 200
    assert capfd.readouterr().err == ""
