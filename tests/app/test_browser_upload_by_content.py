"""Files read by what they hold upload on the Signal page, as the CLI reads them.

The Signal page's uploader took only a list of suffixes (csv, tsv, txt, dat, npy, nmea and
the log readers'), so an RTKLIB ``.pos`` solution or a LAS well log, which
``noisevar estimate`` reads by its content (``noisevar.io.load``), was turned away in the
browser ("file type not allowed"): one record, two answers. The uploader now takes any
file and the loader reads or refuses it in one line.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from test_browser_pages import VIEWPORTS, upload_then_open  # noqa: E402

from tests.test_io_audit18 import _las  # noqa: E402

_POS_HEAD = (
    "% program   : RTKPOST ver.2.4.3\n% pos mode  : single\n%\n"
    "% (lat/lon/height=WGS84/ellipsoidal,Q=1:fix,2:float,3:sbas,4:dgps,5:single,6:ppp,"
    "ns=# of satellites)\n"
    "%  GPST                  latitude(deg) longitude(deg)  height(m)   Q  ns   sdn(m)   "
    "sde(m)   sdu(m)  sdne(m)  sdeu(m)  sdun(m) age(s)  ratio\n"
)


def _pos(n: int = 400, seed: int = 1) -> str:
    """A still antenna's single-point solution, one fix a second."""
    rng = np.random.default_rng(seed)
    lat = 48.8371 + rng.normal(0.0, 2e-5, n)
    lon = 2.4215 + rng.normal(0.0, 3e-5, n)
    h = 90.0 + rng.normal(0.0, 5.0, n)
    rows = [
        f"2021/07/16 09:{46 + (i // 60):02d}:{i % 60:06.3f} {a:14.9f} {b:14.9f} {c:10.4f}"
        "   5   7   2.6685   2.0172   6.6754   1.1774   0.8418   1.1303   0.00    0.0"
        for i, (a, b, c) in enumerate(zip(lat, lon, h, strict=True))
    ]
    return _POS_HEAD + "\n".join(rows) + "\n"


@pytest.mark.parametrize(
    ("name", "text", "said"),
    [("rover.pos", _pos(), "up_m"), ("well.las", _las(600)[0], "GAPI")],
)
def test_a_file_read_by_its_content_uploads(server, browser, tmp_path, name, text, said):
    path = tmp_path / name
    path.write_text(text)
    ctx = browser.new_context(viewport=VIEWPORTS["desktop"])
    page = ctx.new_page()
    main = upload_then_open(page, server, path, "Signal", "Signal")
    assert "not allowed" not in page.inner_text("body")
    main.get_by_text(said).first.wait_for(timeout=60_000)  # a channel or its unit shown
    assert main.locator('[data-testid="stException"]').count() == 0
    ctx.close()
