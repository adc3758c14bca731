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
"""

from __future__ import annotations

import io
import json
import sys
import threading
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from urllib.parse import urlsplit

from ..errors import InputError

__all__ = ["ViewServer", "register", "run"]

HOST = "127.0.0.1"  # never another interface: the page can change what this process computes
_MAX_BODY = 65536


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
    Usable as a context manager.
    """

    def __init__(self, preview, *, port: int = 0, verbose: bool = False):
        from .view_page import PAGE

        self.preview = preview
        self.verbose = verbose
        self._page = PAGE.encode("utf-8")
        self._frame_lock = threading.Lock()  # one frame at a time: a pass, then its encoding
        self._cache: tuple | None = None  # (key, jpeg bytes) of the last frame
        self.frames = 0  # frames served
        server = self

        class Handler(BaseHTTPRequestHandler):
            def log_message(self, format, *args):  # noqa: A002 (the base class's name)
                if server.verbose:
                    super().log_message(format, *args)

            def do_GET(self):
                server._get(self)

            def do_POST(self):
                server._post(self)

        try:
            self.httpd = ThreadingHTTPServer((HOST, int(port)), Handler)
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
        for k, v in (headers or {}).items():
            h.send_header(k, v)
        h.end_headers()
        h.wfile.write(body)

    def _json(self, h, status, obj) -> None:
        self._send(h, status, json.dumps(obj).encode("utf-8"), "application/json")

    def _get(self, h) -> None:
        path = urlsplit(h.path).path
        try:
            if path in ("/", "/index.html"):
                self._send(h, HTTPStatus.OK, self._page, "text/html; charset=utf-8")
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
                self._json(h, HTTPStatus.NOT_FOUND, {"error": f"no such page: {path}"})
        except (BrokenPipeError, ConnectionResetError):
            pass  # the page went away mid-answer

    def _post(self, h) -> None:
        path = urlsplit(h.path).path
        if path != "/controls":
            self._json(h, HTTPStatus.NOT_FOUND, {"error": f"no such endpoint: {path}"})
            return
        try:
            n = int(h.headers.get("Content-Length") or 0)
        except ValueError:
            n = -1
        if not 0 < n <= _MAX_BODY:
            self._json(
                h, HTTPStatus.BAD_REQUEST, {"error": f"expected a JSON body of 1 to {_MAX_BODY} bytes"}
            )
            return
        try:
            values = json.loads(h.rfile.read(n).decode("utf-8"))
            generation = self.preview.update(values)
        except (ValueError, UnicodeDecodeError) as exc:  # InputError is a ValueError, as is bad JSON
            self._json(h, HTTPStatus.BAD_REQUEST, {"error": str(exc).splitlines()[0]})
            return
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
