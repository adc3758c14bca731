import os

import pytest

import warpoptics as wo


def _devices():
    # default "cpu"; add more with WARPOPTICS_TEST_DEVICES="cpu,cuda:0"
    names = os.environ.get("WARPOPTICS_TEST_DEVICES", "cpu")
    return [n.strip() for n in names.split(",") if n.strip()]


@pytest.fixture(params=_devices())
def device(request):
    return wo.device.get_device(request.param)
