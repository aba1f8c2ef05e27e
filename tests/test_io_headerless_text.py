"""A headerless table whose rows end in text (tracklib's photo log: a GPS time, east, north,
height, three angles, the photo's file name): its first line was read as the header, so the
columns were named by the first epoch's numbers and that epoch was lost."""

from __future__ import annotations

import numpy as np

from noisevar.io import load_table


def _photo_log(n: int, seed: int) -> tuple[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    east = 658272.0 + rng.normal(0, 0.05, n)
    rows = [f"{392812.7 + 2.1 * i:.6f} {east[i]:.3f} {6860574.6 - 5 * i:.3f} 52.983 "
            f"TestVincennes_1909121306_04_{805 + i:05d}_0.tif" for i in range(n)]  # fmt: skip
    return "\n".join(rows) + "\n", east


def test_first_line_of_a_headerless_log_is_a_row(tmp_path):
    text, east = _photo_log(50, seed=1)
    path = tmp_path / "photos.txt"
    path.write_text(text)
    table = load_table(path)
    assert list(table.columns)[:4] == ["col0", "col1", "col2", "col3"]
    np.testing.assert_allclose(table.columns["col1"], np.round(east, 3))
    # a header's names differ from the text under them in more than digits: still a header
    path = tmp_path / "labels.csv"
    path.write_text("name,2019,2020\n" + "".join(f"A{i},{i},{i + 1}\n" for i in range(9)))
    table = load_table(path)
    assert "2019" in table.columns and table.columns["2019"].size == 9
