"""`warpoptics info`: device, Warp version, kernel cache."""

from __future__ import annotations

import os


def _dir_size(path: str) -> int:
    total = 0
    for root, _dirs, files in os.walk(path):
        for f in files:
            try:
                total += os.path.getsize(os.path.join(root, f))
            except OSError:
                pass
    return total


def run(args) -> int:
    import warp as wp

    from .. import __version__
    from ..device import cpu_threads, get_device

    dev = get_device(args.device)
    cache = wp.config.kernel_cache_dir or ""
    size = _dir_size(cache) if cache and os.path.isdir(cache) else 0
    print(f"warpoptics     {__version__}")
    print(f"warp           {wp.config.version}")
    print(f"device         {dev.alias} ({dev.name})")
    print(f"devices        {', '.join(d.alias for d in wp.get_devices())}")
    print(f"cpu threads    {cpu_threads()}")
    print(f"kernel cache   {cache} ({size / 2**20:.1f} MiB)")
    return 0


def register(sub) -> None:
    p = sub.add_parser("info", help="show the device, Warp version and kernel cache")
    p.set_defaults(func=run)
