"""Property-based fuzz of scene TOML: random keys, types and extreme values
over every schema field of a small valid scene.  Each case must end in exactly one of two ways:

- a one-line :class:`~warpoptics.errors.InputError` (the CLI's exit 2), or
- a scene that builds, and — where the work is small enough to render here (pixels x spp x
  wavelengths within a budget) — an image with finite XYZ and Stokes values;

never another exception (a traceback), a hang (each case has a timeout) or non-finite pixels.

CI runs a small, derandomized budget (``WARPOPTICS_FUZZ_EXAMPLES``, default 25).  A longer local
run: ``WARPOPTICS_FUZZ_EXAMPLES=2000 WARPOPTICS_FUZZ_REPORT=fuzz.json python -m pytest
tests/test_fuzz_scene.py -q`` (random seeds; the report counts the outcomes).
"""

from __future__ import annotations

import copy
import dataclasses
import inspect
import json
import math
import os
import signal
from collections import Counter

import numpy as np
import pytest
from _helpers import BASE, FILE

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from warpoptics.errors import InputError  # noqa: E402

EXAMPLES = int(os.environ.get("WARPOPTICS_FUZZ_EXAMPLES", "25"))
REPORT = os.environ.get("WARPOPTICS_FUZZ_REPORT")
CASE_TIMEOUT_S = int(os.environ.get("WARPOPTICS_FUZZ_TIMEOUT", "120"))  # a loaded 2-core CI machine
# render a case only when it is this small (pixels x spp x wavelengths); larger valid scenes are
# built (validated, geometry and materials made) but not traced: the question here is a clear
# answer, not a long render
RENDER_BUDGET = 4 * 4 * 4 * 8


def _fields() -> dict[str, list[str]]:
    """Every schema field, per table, from the schema itself (so that a new field is fuzzed)."""
    from warpoptics.geometry import cuts
    from warpoptics.materials import spec as mspec
    from warpoptics.scene import schema
    from warpoptics.stages.camera import CameraConfig

    shape_params: set[str] = {"diameter"}
    for name in schema.SHAPES:
        fn = getattr(cuts, name, None)
        if fn is not None:
            shape_params |= {p for p in inspect.signature(fn).parameters if p != "kw"}
    lamp = set().union(*schema._LAMP_KEYS.values())
    surf = set().union(*schema._SURFACE_KEYS.values())
    render = {f.name for f in dataclasses.fields(schema.RenderConfig) if f.name != "source"}
    return {
        "camera": sorted(f.name for f in dataclasses.fields(CameraConfig) if f.name != "source"),
        "render": sorted(render),
        "light.0": sorted(schema._LIGHT_KEYS | lamp),
        "object.0": sorted(schema._OBJECT_COMMON | shape_params),
        "object.0.material": sorted(mspec._KEYS),
        "object.0.material.bands.0": sorted(mspec._BAND_KEYS),
        "surface.0": sorted(surf),
        "view": sorted(schema._VIEW_KEYS),
    }


FIELDS = _fields()

# words the schema knows (so that fuzzed strings sometimes pass the first check and reach deeper)
WORDS = [
    "diamond", "sapphire", "calcite", "water", "studio", "dome", "constant", "environment", "area",
    "directional", "spot", "plane", "rectangle", "mesh", "gemcad", "step_cut", "round_brilliant",
    "sphere", "prism", "rgb3", "uniform", "importance", "stratified", "exact", "approx", "orthographic",
    "thin_lens", "perspective", "analyzer", "polariscope", "lorentzian", "gaussian", "ggx", "lambert",
    "filmic", "clip", "x.png", "missing.obj", "", "abc",
]  # fmt: skip

EXTREME = [
    0, 1, -1, 2, 3, 7, 2**31 - 1, 2**31, 2**34, 2**63, 10**9, 0.0, -0.0, 1e-308, 1e-9, 1e-3, 0.5,
    1.0, 1.5, 45.0, 89.9, 90.0, 180.0, 1e6, 3e38, 1e308, math.inf, -math.inf, math.nan,
]  # fmt: skip

# plausible values (small counts, angles and sizes, vectors, library words) get past the first
# type check and exercise the deeper checks and the renderer; the rest are hostile
mild = st.one_of(
    st.integers(min_value=0, max_value=64),
    st.floats(min_value=-100.0, max_value=100.0),
    st.lists(st.floats(min_value=-50.0, max_value=50.0), min_size=3, max_size=3),
    st.lists(st.floats(min_value=0.0, max_value=2.0), min_size=3, max_size=3),
    st.sampled_from(WORDS),
)
scalars = st.one_of(
    mild,
    mild,
    st.sampled_from(EXTREME),
    st.integers(min_value=-(2**64), max_value=2**64),
    st.floats(allow_nan=True, allow_infinity=True),
    st.booleans(),
    st.sampled_from(WORDS),
    st.text(max_size=6),
)
values = st.recursive(
    scalars,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4),
        st.lists(st.sampled_from(EXTREME), min_size=2, max_size=3),
        st.dictionaries(st.sampled_from(WORDS[:8] + ["n", "center_nm", "base"]), inner, max_size=3),
    ),
    max_leaves=8,
)


@st.composite
def edits(draw):
    """1-4 edits: (table, key, value); a key is a schema field or, sometimes, an unknown one."""
    out = []
    for _ in range(draw(st.sampled_from([1, 1, 1, 2, 2, 3, 4]))):
        table = draw(st.sampled_from(sorted(FIELDS)))
        key = draw(
            st.one_of(st.sampled_from(FIELDS[table]), st.sampled_from(FIELDS[table]), st.text(max_size=5))
        )
        out.append((table, key, draw(values)))
    return out


def _apply(data: dict, table: str, key: str, value) -> None:
    node = data
    parts = table.split(".")
    for i, p in enumerate(parts):
        if p.isdigit():
            lst = node
            while len(lst) <= int(p):
                lst.append({"type": "plane", "height": -1.0} if parts[i - 1] == "surface" else {})
            node = lst[int(p)]
        else:
            if p == "material" and isinstance(node.get(p), str):
                node[p] = {"base": node[p]}
            if p in ("bands",) and not isinstance(node.get(p), list):
                node[p] = []
            if p in ("surface",) and not isinstance(node.get(p), list):
                node[p] = []
            if not isinstance(node.get(p), (dict, list)):
                node[p] = {}
            node = node[p]
    if isinstance(node, dict):
        node[key] = value


class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout()


_COUNTS: Counter = Counter()


@pytest.fixture(scope="module", autouse=True)
def _warm_and_report():
    """Compile the renderer's kernels once (outside the per-case timeout) and, at the end, write
    the outcome counts where WARPOPTICS_FUZZ_REPORT says."""
    from warpoptics.pipelines.render import Renderer
    from warpoptics.scene import Scene

    Renderer(Scene.from_dict(copy.deepcopy(BASE), path=FILE)).run()
    yield
    if REPORT:
        with open(REPORT, "w", encoding="utf-8") as f:  # not-a-replace: a test's report file
            json.dump(dict(_COUNTS), f, indent=1, sort_keys=True)


def _work(scene) -> int:
    c, r = scene.camera, scene.render
    return c.width * c.height * r.spp * r.wavelengths * (1 + r.caustic_paths)


@settings(
    max_examples=EXAMPLES,
    deadline=None,
    derandomize=EXAMPLES <= 100,
    database=None,
    suppress_health_check=list(HealthCheck),
)
@given(edits())
def test_fuzzed_scene_is_a_clear_error_or_a_finite_image(edit_list):
    from warpoptics.pipelines.render import Renderer
    from warpoptics.scene import Scene

    data = copy.deepcopy(BASE)
    for table, key, value in edit_list:
        _apply(data, table, key, value)
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(CASE_TIMEOUT_S)
    try:
        try:
            scene = Scene.from_dict(data, path=FILE)
            renderer = Renderer(scene)
            if _work(scene) > RENDER_BUDGET:
                _COUNTS["built, not rendered (large)"] += 1
                return
            img = renderer.run()
        except InputError as exc:
            msg = str(exc)
            assert "\n" not in msg and len(msg) < 2000, f"not one line: {msg[:3000]}"
            _COUNTS["InputError"] += 1
            return
        except _Timeout:
            _COUNTS["HANG"] += 1
            raise AssertionError(f"no answer within {CASE_TIMEOUT_S} s: {edit_list!r}") from None
        except Exception as exc:
            _COUNTS[f"traceback {type(exc).__name__}"] += 1
            raise AssertionError(f"{type(exc).__name__}: {exc} for {edit_list!r}") from exc
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    finite = bool(np.isfinite(img.xyz).all() and np.isfinite(img.stokes).all())
    _COUNTS["rendered, finite" if finite else "NON-FINITE"] += 1
    assert finite, f"non-finite pixels for {edit_list!r}"
