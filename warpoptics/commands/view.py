"""`warpoptics view SCENE.toml`: a progressive preview in a local web page.

The server (``http.server``, bound to 127.0.0.1 only) drives a
:class:`~warpoptics.pipelines.preview.Preview`: every request for a frame adds one pass and
answers with the mean so far as a JPEG (Pillow), so the image refines for as long as a page
watches it and the machine is idle when none does.  Endpoints:

``GET /``            the page (:mod:`.view_page`)
``GET /state``       JSON: image size, passes, generation, seconds of the last pass, the controls
``GET /frame.jpg``   one more pass, then the image; headers ``X-Passes``, ``X-Generation``,
                     ``X-Draft`` (1: the low-resolution draft after a restart, ``X-Passes`` 0),
                     ``X-Pass-Seconds``, ``X-Done`` (1 once ``max_passes`` are in)
``GET /frame.png``   the image as it is (no new pass), lossless
``POST /controls``   JSON ``{name: value}``: 200 with the new generation and values, or 400 with
                     the one-line error (nothing changed)

Who may ask (docs/preview_security.md): every request must name this server in ``Host``
(``127.0.0.1:PORT``, ``localhost:PORT`` or ``[::1]:PORT``; else 403), which defeats DNS
rebinding: a page of another site whose name was made to resolve to 127.0.0.1 sends its own name;
and a browser's ``Sec-Fetch-Site``, when sent, must be ``same-origin`` or ``none`` (else 403: an
``<img>`` of another site's page may not make this machine render).
A write (any POST) must also come from the page itself: ``Origin`` (when sent) one of those
hosts, ``Content-Type: application/json`` (else 415: a form or a ``no-cors`` fetch of another
site cannot send it without a preflight, which this server never grants) and the header
``X-Warpoptics-Token`` equal to the random token of this launch that only the served page holds
(else 403).  The body is at most :data:`MAX_BODY` bytes (413 beyond, 411 without a length);
a body that is cut short, not JSON, nested too deeply, not an object, or names an unknown control
or a non-finite value is answered 400, never a traceback.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import secrets
import sys
import threading
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from urllib.parse import urlsplit

from ..errors import InputError

__all__ = ["ViewServer", "register", "run"]

HOST = "127.0.0.1"  # never another interface: the page can change what this process computes
MAX_BODY = 65536  # bytes of a POST body
TOKEN_HEADER = "X-Warpoptics-Token"
TOKEN_PLACEHOLDER = "@WARPOPTICS_TOKEN@"  # in view_page.PAGE: replaced by the launch's token
_READ_TIMEOUT = 30.0  # seconds a client may take to send its request (a stalled body: 408)


def allowed_hosts(port: int) -> frozenset[str]:
    """The ``Host`` values that name this server (lower case): the loopback names with the port
    (and without it on port 80, as browsers send it there)."""
    names = ("127.0.0.1", "localhost", "[::1]")
    hosts = {f"{n}:{int(port)}" for n in names}
    if int(port) == 80:
        hosts.update(names)
    return frozenset(hosts)


def _finite_float(text: str) -> float:
    x = float(text)
    if not math.isfinite(x):
        raise ValueError(f"a number beyond the float range: {text[:40]}")
    return x


def _no_constant(name: str):
    raise ValueError(f"{name} is not a JSON number")


class _Refused(Exception):
    """A request answered with an error status: ``status`` and a one-line ``message``."""

    def __init__(self, status: HTTPStatus, message: str):
        super().__init__(message)
        self.status = status


def _encode(rgb, fmt: str) -> bytes:
    from PIL import Image as PILImage

    buf = io.BytesIO()
    if fmt == "JPEG":
        # no chroma subsampling (4:4:4): a gem's fire is colour detail at the scale of a pixel
        PILImage.fromarray(rgb).save(buf, "JPEG", quality=90, subsampling=0)
    else:
        PILImage.fromarray(rgb).save(buf, "PNG")
    return buf.getvalue()


class ViewServer:
    """An HTTP server for a preview on ``127.0.0.1:port`` (0: any free port, see :attr:`port`).

    ``start()`` serves from a background thread; ``shutdown()`` stops it and closes the socket.
    Usable as a context manager.  :attr:`token` is this launch's write token (embedded in the
    page; see the module docstring for what each request must carry).
    """

    def __init__(self, preview, *, port: int = 0, verbose: bool = False):
        from .view_page import PAGE

        self.preview = preview
        self.verbose = verbose
        self.token = secrets.token_urlsafe(32)
        self._page = PAGE.replace(TOKEN_PLACEHOLDER, self.token).encode("utf-8")
        self._frame_lock = threading.Lock()  # one frame at a time: a pass, then its encoding
        self._cache: tuple | None = None  # (key, jpeg bytes) of the last frame
        self.frames = 0  # frames served
        server = self

        class Handler(BaseHTTPRequestHandler):
            timeout = _READ_TIMEOUT  # a client that stops sending mid-request frees its thread

            def log_message(self, format, *args):  # noqa: A002 (the base class's name)
                if server.verbose:
                    super().log_message(format, *args)

            def do_GET(self):
                server._answer(self, server._get)

            def do_POST(self):
                server._answer(self, server._post)

        class Server(ThreadingHTTPServer):
            def handle_error(self, request, client_address):
                # what escaped a handler: a client gone before its request line (quiet), else one
                # line, never a traceback
                exc = sys.exc_info()[1]
                if not isinstance(exc, (BrokenPipeError, ConnectionResetError, TimeoutError)):
                    print(f"warpoptics view: a request failed: {type(exc).__name__}: {exc}", file=sys.stderr)

        try:
            self.httpd = Server((HOST, int(port)), Handler)
        except OSError as exc:
            raise InputError(
                f"cannot listen on {HOST}:{port} ({exc.strerror})", field="--port", value=port
            ) from None
        self.httpd.daemon_threads = True
        self._thread: threading.Thread | None = None

    @property
    def port(self) -> int:
        return int(self.httpd.server_address[1])

    @property
    def url(self) -> str:
        return f"http://{HOST}:{self.port}/"

    def start(self) -> ViewServer:
        self._thread = threading.Thread(target=self.httpd.serve_forever, name="warpoptics-view", daemon=True)
        self._thread.start()
        return self

    def shutdown(self) -> None:
        if self._thread is not None:
            self.httpd.shutdown()
            self._thread.join(timeout=30)
            self._thread = None
        self.httpd.server_close()

    def __enter__(self) -> ViewServer:
        return self.start()

    def __exit__(self, *exc) -> None:
        self.shutdown()

    # -- requests -------------------------------------------------------------------------------
    def state(self) -> dict:
        p = self.preview
        return {
            "width": p.width,
            "height": p.height,
            "passes": p.passes,
            "max_passes": p.max_passes,
            "generation": p.generation,
            "pass_seconds": p.seconds,
            "controls": [c.as_dict() for c in p.controls()],
        }

    def frame(self, *, step: bool = True) -> tuple[bytes, dict]:
        """One more pass (``step``), then the JPEG of the mean so far and its headers."""
        p = self.preview
        with self._frame_lock:
            if step:
                p.step()
            key = (p.generation, p.passes, p.showing_draft, p.exposure)
            if self._cache is None or self._cache[0] != key:
                self._cache = (key, _encode(p.frame(), "JPEG"))
            self.frames += 1
            headers = {
                "X-Passes": str(p.passes),
                "X-Generation": str(p.generation),
                "X-Draft": "1" if p.showing_draft else "0",
                "X-Pass-Seconds": f"{p.seconds:.4f}",
                "X-Done": "1" if p.passes >= p.max_passes else "0",
            }
            return self._cache[1], headers

    def _send(self, h, status, body: bytes, ctype: str, headers: dict | None = None) -> None:
        h.send_response(status)
        h.send_header("Content-Type", ctype)
        h.send_header("Content-Length", str(len(body)))
        h.send_header("Cache-Control", "no-store")
        h.send_header("X-Content-Type-Options", "nosniff")
        for k, v in (headers or {}).items():
            h.send_header(k, v)
        h.end_headers()
        h.wfile.write(body)

    def _json(self, h, status, obj) -> None:
        self._send(h, status, json.dumps(obj).encode("utf-8"), "application/json")

    def _answer(self, h, method) -> None:
        """Check the ``Host``, then run ``method``; a refusal becomes its status with a one-line
        JSON error; a client gone mid-request (reset, broken pipe, stalled past the timeout) ends
        the connection quietly."""
        try:
            try:
                host = (h.headers.get("Host") or "").strip().lower()
                if host not in allowed_hosts(self.port):
                    raise _Refused(HTTPStatus.FORBIDDEN, f"this server answers only as {HOST}:{self.port}")
                # a browser says which site's page asks: another's <img>, <script> or frame may
                # not make this machine render (nor read what its answer reveals)
                site = (h.headers.get("Sec-Fetch-Site") or "none").strip().lower()
                if site not in ("same-origin", "none"):
                    raise _Refused(
                        HTTPStatus.FORBIDDEN, f"requests from other sites' pages are refused ({site})"
                    )
                method(h)
            except _Refused as exc:
                h.close_connection = True  # an unread body must not be taken for the next request
                self._json(h, exc.status, {"error": str(exc)})
        except (BrokenPipeError, ConnectionResetError, TimeoutError):
            h.close_connection = True  # the page went away mid-answer
        except Exception as exc:  # a fault of this program, not of the request: 500 and one line
            h.close_connection = True
            message = f"{type(exc).__name__}: {str(exc).splitlines()[0][:500] if str(exc) else ''}"
            print(f"warpoptics view: {h.command} {h.path[:200]} failed: {message}", file=sys.stderr)
            with contextlib.suppress(OSError):
                self._json(h, HTTPStatus.INTERNAL_SERVER_ERROR, {"error": message})

    def _get(self, h) -> None:
        path = urlsplit(h.path).path
        if path in ("/", "/index.html"):
            csp = (
                "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; "
                "img-src 'self' blob:; connect-src 'self'; frame-ancestors 'none'"
            )
            headers = {"Content-Security-Policy": csp, "X-Frame-Options": "DENY"}
            self._send(h, HTTPStatus.OK, self._page, "text/html; charset=utf-8", headers)
        elif path == "/state":
            self._json(h, HTTPStatus.OK, self.state())
        elif path == "/frame.jpg":
            body, headers = self.frame()
            self._send(h, HTTPStatus.OK, body, "image/jpeg", headers)
        elif path == "/frame.png":
            with self._frame_lock:
                body = _encode(self.preview.frame(), "PNG")
            self._send(h, HTTPStatus.OK, body, "image/png")
        else:
            raise _Refused(HTTPStatus.NOT_FOUND, f"no such page: {path[:200]}")

    def _check_write(self, h) -> None:
        """A write must come from the served page: same origin, JSON, this launch's token."""
        origin = h.headers.get("Origin")
        if origin is not None and origin.strip().lower() not in {
            f"http://{x}" for x in allowed_hosts(self.port)
        }:
            raise _Refused(
                HTTPStatus.FORBIDDEN, f"writes are accepted only from this server's page, not {origin[:200]}"
            )
        ctype = (h.headers.get("Content-Type") or "").split(";")[0].strip().lower()
        if ctype != "application/json":
            raise _Refused(HTTPStatus.UNSUPPORTED_MEDIA_TYPE, "expected Content-Type: application/json")
        token = h.headers.get(TOKEN_HEADER) or ""
        if not secrets.compare_digest(token.encode("utf-8", "replace"), self.token.encode("ascii")):
            raise _Refused(
                HTTPStatus.FORBIDDEN, f"missing or wrong {TOKEN_HEADER} (the page of this launch sends it)"
            )

    def _read_json(self, h):
        """The request's body, parsed: at most :data:`MAX_BODY` bytes, strict JSON (no NaN or
        Infinity, no number beyond the float range), any depth Python's parser takes."""
        if h.headers.get("Transfer-Encoding") or h.headers.get("Content-Length") is None:
            raise _Refused(HTTPStatus.LENGTH_REQUIRED, "expected a Content-Length")
        try:
            n = int(h.headers["Content-Length"])
        except ValueError:
            raise _Refused(HTTPStatus.BAD_REQUEST, "Content-Length is not a number") from None
        if n > MAX_BODY:
            raise _Refused(HTTPStatus.REQUEST_ENTITY_TOO_LARGE, f"a body of at most {MAX_BODY} bytes")
        if n <= 0:
            raise _Refused(HTTPStatus.BAD_REQUEST, f"expected a JSON body of 1 to {MAX_BODY} bytes")
        try:
            data = h.rfile.read(n)
        except TimeoutError:
            raise _Refused(
                HTTPStatus.REQUEST_TIMEOUT, f"the body did not arrive within {_READ_TIMEOUT:g} s"
            ) from None
        if len(data) < n:
            raise _Refused(HTTPStatus.BAD_REQUEST, f"the body ended after {len(data)} of {n} bytes")
        try:
            return json.loads(data.decode("utf-8"), parse_float=_finite_float, parse_constant=_no_constant)
        except RecursionError:
            raise _Refused(HTTPStatus.BAD_REQUEST, "the JSON is nested too deeply") from None
        except ValueError as exc:  # bad JSON, bad UTF-8, a non-finite number
            raise _Refused(
                HTTPStatus.BAD_REQUEST, f"not valid JSON: {str(exc).splitlines()[0][:200]}"
            ) from None

    def _post(self, h) -> None:
        path = urlsplit(h.path).path
        self._check_write(h)  # before the path: a foreign page learns nothing from the answer
        if path != "/controls":
            raise _Refused(HTTPStatus.NOT_FOUND, f"no such endpoint: {path[:200]}")
        values = self._read_json(h)
        try:
            generation = self.preview.update(values)
        except (ValueError, OverflowError, RecursionError) as exc:  # InputError is a ValueError
            raise _Refused(HTTPStatus.BAD_REQUEST, str(exc).splitlines()[0][:500]) from None
        self._json(h, HTTPStatus.OK, {"generation": generation, "values": self.preview.values()})


def run(args) -> int:
    from ..pipelines.preview import Preview
    from ..scene.bench import is_bench_scene
    from ..scene.load import Scene, parse_set_options

    if is_bench_scene(args.scene):
        raise InputError("the viewer shows camera scenes; this is an optical-bench scene", file=args.scene)
    val_port = args.port
    if not 0 <= val_port <= 65535:
        raise InputError(
            "not a TCP port", field="--port", value=val_port, allowed="0 (any free port) to 65535"
        )
    scene = Scene.load(args.scene)
    overrides = parse_set_options(args.set)
    if overrides:
        scene = scene.with_overrides(overrides)
    preview = Preview(
        scene,
        width=args.width,
        height=args.height,
        wavelengths=args.wavelengths,
        spectral=args.spectral,
        max_passes=args.max_passes,
        draft_scale=args.draft_scale,
        device=args.device,
        estimator=args.estimator,
    )
    server = ViewServer(preview, port=args.port, verbose=args.verbose)
    print(f"warpoptics view: {server.url}  ({preview.width}x{preview.height}; Ctrl-C to stop)", flush=True)
    if args.open:
        import webbrowser

        webbrowser.open(server.url)
    try:
        server.httpd.serve_forever()
    except KeyboardInterrupt:
        print("warpoptics view: stopped", file=sys.stderr)
    finally:
        server.httpd.server_close()
    return 0


def register(sub) -> None:
    p = sub.add_parser(
        "view", help="progressive preview of a scene in a local web page (orbit, cut, material, light)"
    )
    p.add_argument("scene", help="scene file (.toml)")
    p.add_argument("--width", type=int, default=400, help="preview width in pixels (default 400)")
    p.add_argument("--height", type=int, default=300, help="preview height in pixels (default 300)")
    p.add_argument(
        "--wavelengths",
        type=int,
        default=1,
        help="wavelengths per sample of a pass (default 1; rgb3 keeps 3)",
    )
    p.add_argument(
        "--spectral",
        choices=("importance", "stratified", "uniform", "rgb3"),
        help="how a pass draws its wavelengths (default importance; an rgb3 scene keeps rgb3)",
    )
    p.add_argument(
        "--max-passes",
        type=int,
        default=4096,
        help="stop refining after this many passes (samples per pixel)",
    )
    p.add_argument(
        "--estimator",
        choices=("auto", "beam", "point"),
        default="auto",
        help="the passes: pixel beams in bands of rows where they apply (auto, default), or point samples",
    )
    p.add_argument(
        "--draft-scale",
        type=int,
        default=2,
        help="after every change first show one pass at 1/N of the resolution (default 2; 1: none)",
    )
    p.add_argument(
        "--port", type=int, default=8470, help="TCP port on 127.0.0.1 (default 8470; 0: any free port)"
    )
    p.add_argument("--open", action="store_true", help="open the page in the default web browser")
    p.add_argument(
        "--set",
        action="append",
        metavar="KEY=VALUE",
        help="override any scene value by dotted path before viewing, e.g. --set object.0.pavilion_angle=41",
    )
    p.add_argument("--verbose", action="store_true", help="log every HTTP request")
    p.set_defaults(func=run)
