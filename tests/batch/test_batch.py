"""Batch: a folder with a bad file, rows equal to single-file estimates, resume, CLI."""

from __future__ import annotations

import io
import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import noisevar as nv
from noisevar.batch import expand_paths, read_table, task_size
from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.io import load_table, pick_column

BATCH = sys.modules["noisevar.batch"]
N = 1500


def _write_fleet(root: Path, n_files: int = 6) -> list[Path]:
    """``n_files`` good files (three channels; .npy and CSV), in two folders."""
    rng = np.random.default_rng(11)
    out = []
    for i in range(n_files):
        walk = np.cumsum(rng.normal(0.0, 0.05, (N, 3)), axis=0)
        data = walk + rng.normal(0.0, 1.0 + 0.1 * i, (N, 3))
        folder = root / ("line_a" if i % 2 else "line_b")
        folder.mkdir(parents=True, exist_ok=True)
        if i % 3 == 0:
            path = folder / f"unit{i}.csv"
            np.savetxt(path, data, delimiter=",", header="x,y,z", comments="")
        else:
            path = folder / f"unit{i}.npy"
            np.save(path, data)
        out.append(path)
    return out


@pytest.fixture
def fleet(tmp_path) -> tuple[Path, list[Path]]:
    root = tmp_path / "logs"
    files = _write_fleet(root)
    (root / "line_a" / "broken.csv").write_text("x,y\n1.0,oops\n2.0,3.0\n")
    return root, files


def _single(path: Path, column: str, method: str = "auto", **params) -> nv.VarianceEstimate:
    table = load_table(str(path), path.name)
    return nv.estimate(pick_column(table, column), method=method, **params)


def test_rows_equal_single_file_estimates_and_a_bad_file_is_one_row(fleet, tmp_path):
    root, files = fleet
    frame = nv.batch(str(root / "**" / "*.*"), out=tmp_path / "noise.parquet", progress=False)
    bad = frame[frame["error"].notna()]
    assert list(bad["file"]) == [str(root / "line_a" / "broken.csv")]
    assert "'oops' is not a number" in bad["error"].iat[0]
    good = frame[frame["error"].isna()]
    assert len(good) == 3 * len(files)
    for _, row in good.iterrows():
        est = _single(Path(row["file"]), row["channel"])
        assert row["variance"] == est.variance and row["std"] == est.std
        assert (row["ci95_low"], row["ci95_high"]) == est.ci95
        assert row["n_total"] == N and row["n_used"] == est.n_used
        assert json.loads(row["params"]) == json.loads(json.dumps(est.params))
    assert list(frame["file"]) == sorted(frame["file"])  # sorted by file, channels in order
    on_disk = read_table(tmp_path / "noise.parquet")
    pd.testing.assert_frame_equal(on_disk, frame, check_dtype=False)


def test_columns_and_parameters_reach_every_file(fleet):
    root, files = fleet
    frame = nv.batch(files, columns="col2,col0", method="somd", window=48, progress=False)
    npy = frame[frame["file"].str.endswith(".npy")]
    assert set(npy["channel"]) == {"col2", "col0"} and npy["error"].isna().all()
    csv_rows = frame[frame["file"].str.endswith(".csv")]
    assert list(csv_rows["channel"]) == ["col2", "col0"] * 2  # each missing channel: its own row
    assert csv_rows["error"].str.match(r"no column 'col[20]' in unit[03]\.csv").all()
    row = npy.iloc[0]
    est = _single(Path(row["file"]), "col2", "somd", window=48)
    assert row["variance"] == est.variance
    assert json.loads(row["params"])["window"] == 48


def test_resume_after_an_interruption_does_only_the_rest(fleet, tmp_path):
    root, files = fleet
    out = tmp_path / "noise.csv"
    seen: list[tuple[int, int]] = []

    def stop_after_three(done: int, total: int) -> None:
        seen.append((done, total))
        if done >= 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        nv.batch(root, out=out, progress=stop_after_three)
    assert seen[-1] == (3, 7)
    assert read_table(out)["file"].nunique() == 3  # what was done is kept
    calls: list[tuple[int, int]] = []
    full = nv.batch(root, out=out, progress=lambda d, t: calls.append((d, t)))
    assert calls[-1] == (4, 4)  # only the remaining four files
    fresh = nv.batch(root, progress=False)
    cols = ["file", "channel", "variance", "ci95_low", "ci95_high", "hash", "error"]
    pd.testing.assert_frame_equal(full[cols], fresh[cols], check_dtype=False)
    again: list[tuple[int, int]] = []
    nv.batch(root, out=out, progress=lambda d, t: again.append((d, t)))
    assert again[-1] == (0, 0)


def test_a_killed_batch_resumes_from_its_journal(fleet, tmp_path, monkeypatch):
    root, files = fleet
    out = tmp_path / "noise.parquet"

    def killed(*args, **kwargs):
        raise SystemExit("killed before the output was written")

    monkeypatch.setattr(BATCH, "_finish", killed)
    with pytest.raises(SystemExit):
        nv.batch(root, out=out, progress=False)
    monkeypatch.undo()
    assert not out.exists() and (tmp_path / "noise.parquet.journal.jsonl").is_file()
    calls: list[tuple[int, int]] = []
    frame = nv.batch(root, out=out, progress=lambda d, t: calls.append((d, t)))
    assert calls[-1] == (0, 0) and frame["file"].nunique() == 7
    assert not (tmp_path / "noise.parquet.journal.jsonl").exists()


def test_a_changed_file_is_redone_and_no_resume_redoes_all(fleet, tmp_path):
    root, files = fleet
    out = tmp_path / "noise.parquet"
    first = nv.batch(root, out=out, progress=False)
    np.save(files[1], np.load(files[1])[:1000])
    calls: list[tuple[int, int]] = []
    second = nv.batch(root, out=out, progress=lambda d, t: calls.append((d, t)))
    assert calls[-1] == (1, 1)
    changed = second[second["file"] == str(files[1])]
    assert (changed["n_total"] == 1000).all()
    assert set(changed["hash"]) != set(first.loc[first["file"] == str(files[1]), "hash"])
    calls.clear()
    nv.batch(root, out=out, resume=False, progress=lambda d, t: calls.append((d, t)))
    assert calls[-1] == (7, 7)
    calls.clear()
    other = nv.batch(root, out=out, method="diff2", progress=lambda d, t: calls.append((d, t)))
    assert calls[-1] == (7, 7) and set(other["method"]) == {"diff2"}  # a new request redoes all
    assert json.loads(other["request"].iat[0])["method"] == "diff2"


def test_two_local_processes_give_the_same_rows(fleet):
    root, files = fleet
    one = nv.batch(root, progress=False)
    two = nv.batch(root, jobs=2, progress=False)
    pd.testing.assert_frame_equal(
        one.drop(columns="elapsed_s"), two.drop(columns="elapsed_s"), check_dtype=False
    )


def test_bad_arguments_are_one_sentence(fleet, tmp_path):
    root, _ = fleet
    with pytest.raises(NoisevarError, match="no file matches"):
        nv.batch(str(tmp_path / "nothing" / "*.csv"))
    with pytest.raises(NoisevarError, match=r"\.parquet or \.csv"):
        nv.batch(root, out=tmp_path / "noise.xlsx")
    with pytest.raises(NoisevarError, match="jobs"):
        nv.batch(root, jobs=0)
    with pytest.raises(NoisevarError, match="second sensor"):
        nv.batch(root, method="somd-redundant")
    with pytest.raises(NoisevarError, match="window"):
        nv.batch(root, method="somd", window=-3)


def test_paths_and_task_sizes():
    assert task_size(2000, 2) == 64 and task_size(10, 2) == 1 and task_size(300, 4) == 10
    assert expand_paths([]) == []


def test_cli_batch_writes_parquet_and_resumes(fleet, tmp_path, capsys):
    root, files = fleet
    out = tmp_path / "noise.parquet"
    pattern = str(root / "**" / "*.npy")
    code = main(["batch", pattern, "--out", str(out), "--method", "diff2", "--quiet"])
    _, err = capsys.readouterr()
    assert code == 0 and "4 files, 12 rows, 0 with an error" in err
    frame = read_table(out)
    row = frame.iloc[0]
    assert row["variance"] == _single(Path(row["file"]), row["channel"], "diff2").variance
    code = main(["batch", pattern, "--columns", "col1", "--quiet"])
    stdout, _ = capsys.readouterr()
    printed = pd.read_csv(io.StringIO(stdout))
    assert code == 0 and list(printed["channel"]) == ["col1"] * 4
    code = main(["batch", str(tmp_path / "none" / "*.csv")])
    _, err = capsys.readouterr()
    assert code == 2 and "no file matches" in err
