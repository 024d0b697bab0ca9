"""The claims atlas (``cross_check.atlas``) on a local Dask cluster, in its Zarr store: a tiny atlas,
the closed-form boundaries within one grid cell, the same values for 1 and 2 workers and any
chunk, nothing lost when a worker is killed, a client killed with SIGKILL resumed to the same
store, a running scheduler given by address, the report and PNGs read from the store."""
import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

distributed = pytest.importorskip("distributed", reason="the atlas needs dask.distributed (the atlas extra)")
xr = pytest.importorskip("xarray", reason="the atlas store needs xarray (the atlas extra)")
zarr = pytest.importorskip("zarr", reason="the atlas store needs zarr (the atlas extra)")

from cross_check import __main__ as cli  # noqa: E402
from cross_check.atlas import Grid, claims, compute, maps, open_atlas, store, summarize  # noqa: E402
from cross_check.report import sections  # noqa: E402

N = 12
ALL = list(claims.CLAIMS)


@pytest.fixture(scope="module")
def atlas_dir(client, tmp_path_factory):
    out = tmp_path_factory.mktemp("atlas")
    stats = compute(ALL, Grid(N), out, client=client, chunk=4)
    assert stats["computed"] == stats["chunks"] == 12 and stats["workers"] == 2
    return out


@pytest.fixture(scope="module")
def atlas(atlas_dir):
    return open_atlas(atlas_dir).load()


def _same_values(a, b, names):
    """Every named variable (and both coordinates) equal, value for value (NaN = NaN)."""
    for name in list(names) + ["f_over_F", "w2R_over_F", "done"]:
        assert a[name].equals(b[name]), name


def test_store_layout(atlas_dir, atlas):
    ds = xr.open_zarr(atlas_dir / "atlas.zarr")
    assert ds.sizes == {"w2R_over_F": N, "f_over_F": N + 1, "example": store.N_EXAMPLES}
    assert np.array_equal(ds["f_over_F"], Grid(N).fF) and np.array_equal(ds["w2R_over_F"], Grid(N).R)
    for name in ("x1", "x2", "x1_trace", "printed", "period3", "period5", "no_impact", "sticks",
                 "dissip_fraction", "area_defect"):
        assert ds[name].dims == ("w2R_over_F", "f_over_F") and ds[name].attrs["long_name"], name
    assert set(ds.data_vars) == set(store.variables(ALL)) | {"done"}
    assert bool(ds["done"].all()) and ds["x1"].encoding["chunks"] == (4, 4)
    assert ds.attrs["grid"] == "12x12" and ds.attrs["claims"] == ALL and ds.attrs["versions"]["zarr"]
    # undefined is NaN: printed beyond the fold, x1's trace where x1 does not exist
    beyond = atlas["f_over_F"].values > claims.FOLD
    printed = atlas["printed"].values
    assert np.isnan(printed[:, beyond]).all() and np.isin(printed[:, ~beyond], [0, 1]).all()
    assert np.array_equal(np.isfinite(atlas["x1_trace"].values), atlas["x1"].values)


@pytest.mark.parametrize("boundary", ["x1: fold f/F = 2/pi", "x2: w^2 R/F = sqrt(4 - pi^2 (f/F)^2)",
                                      "period 3: f/F = 2/(3 pi)", "no impact (f = 0): w^2 R/F = 2",
                                      "attractor sticks: f/F = 1/sqrt(1 + pi^2/4)"])
def test_computed_boundary_within_one_cell_of_the_closed_form(atlas, boundary):
    worst, lines = maps.boundaries(atlas)[boundary]
    assert lines >= 1 and worst <= 1.0, (boundary, worst, lines)


def test_boundaries_see_a_moved_switch(atlas):
    """The boundary check can fail: x1 cut off two columns before the fold is two cells off."""
    moved = atlas.copy()
    moved["x1"] = atlas["x1"] & (atlas["f_over_F"] < claims.FOLD - 2 / N)
    worst, _ = maps.boundaries(moved)["x1: fold f/F = 2/pi"]
    assert worst > 1.0


def test_dissip_violations_are_confirmed_by_the_reference(atlas):
    seen = atlas["dissip_fraction"] > 0
    assert bool(seen.any()) and bool((atlas["dissip_confirmed"].where(seen) == 1).sum() == seen.sum())
    assert bool(atlas["dissip_example_x"].isel(example=0).where(seen).notnull().sum() == seen.sum())


def test_area_is_preserved_on_non_sticking_starts(atlas):
    dets = atlas["area_defect"].values
    assert np.isfinite(dets).any() and np.nanmax(dets) < 1e-9          # claim_unit_det


def test_a_killed_worker_loses_no_result(atlas, client, tmp_path):
    killed = []

    def kill_one(_msg):
        if not killed:
            pid = next(iter(client.run(os.getpid).values()))
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    compute(["symmetric", "no-impact"], Grid(N), tmp_path, client=client, chunk=3, progress=kill_one)
    assert killed
    _same_values(open_atlas(tmp_path).load(), atlas, store.variables(["symmetric", "no-impact"]))


def _atlas_cli(out, *args):
    cmd = [sys.executable, "-m", "cross_check", "atlas", "--grid", str(N), "--chunk", "3", "--claim", "symmetric",
           "--out", str(out), *args]
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def test_a_killed_run_resumes_to_the_same_store(atlas, client, tmp_path):
    """SIGKILL the client (its own 1-worker cluster) after its first chunk is written; the rerun
    (on the running cluster, by address) skips the written chunks and the store equals an
    uninterrupted run's (2 workers, another chunk: the same values)."""
    proc = _atlas_cli(tmp_path, "--workers", "1")
    path, deadline = tmp_path / "atlas.zarr", time.monotonic() + 120
    done = 0
    while not done and proc.poll() is None and time.monotonic() < deadline:
        try:
            done = int(zarr.open_group(str(path), mode="r")["done"][...].sum())
        except (FileNotFoundError, KeyError, ValueError):
            pass
        time.sleep(0.02)
    proc.kill()
    proc.communicate()
    marks = zarr.open_group(str(path), mode="r")["done"][...]
    written = {k for k, rows, cols in Grid(N).blocks(3) if marks[rows, cols].all()}
    assert done and 0 < len(written) < 20, "killed partway: some chunks written, not all"
    with pytest.raises(ValueError, match="not complete"):
        open_atlas(tmp_path)
    again = _atlas_cli(tmp_path, "--scheduler", client.scheduler.address)
    out, err = again.communicate(timeout=300)
    assert again.returncode == 0, err
    skipped = err.split("already written, skipped: ")[1].splitlines()[0]
    assert written <= {int(k) for k in skipped.split(", ")}
    assert f"resuming {path}: " in err and f"chunk {min(written)} written" not in err
    _same_values(open_atlas(tmp_path).load(), atlas, store.variables(["symmetric"]))


@pytest.fixture(scope="module")
def small_dir(client, tmp_path_factory):
    """A 5 x 3 atlas of one cheap claim, made by the CLI on the running scheduler, by address."""
    out = tmp_path_factory.mktemp("small")
    address = client.scheduler.address
    assert address.startswith("tcp://127.0.0.1:")
    assert cli.main(["atlas", "--scheduler", address, "--grid", "5x3", "--chunk", "2", "--claim",
                     "area-preservation", "--out", str(out)]) == 0
    return out


def test_scheduler_by_address_and_a_non_square_grid(small_dir, capsys):
    ds = open_atlas(small_dir)
    assert ds.sizes["f_over_F"] == 6 and ds.sizes["w2R_over_F"] == 3 and ds.attrs["grid"] == "5x3"
    assert np.array_equal(ds["w2R_over_F"], Grid(5, 3).R) and np.array_equal(ds["f_over_F"], Grid(5, 3).fF)
    assert (small_dir / "atlas_area-preservation.png").stat().st_size > 5000
    args = ["atlas", "--grid", "3x5", "--chunk", "2", "--claim", "area-preservation", "--out", str(small_dir)]
    capsys.readouterr()
    assert cli.main(args) == 2
    err = capsys.readouterr().err
    assert "holds another atlas: grid '5x3' (this run: '3x5')" in err and "Traceback" not in err
    assert cli.main([*args[:2], "5x3", *args[3:6], "symmetric", *args[7:]]) == 2
    assert "claims ['area-preservation'] (this run: ['symmetric'])" in capsys.readouterr().err


@pytest.mark.parametrize("text, nf, nr, chunk", [("64", 64, 64, 16), ("256x64", 256, 64, 16), (" 7X3 ", 7, 3, 1),
                                                ("8", 8, 8, 2)])
def test_grid_names(text, nf, nr, chunk):
    g = Grid.parse(text)
    assert (g.nf, g.nr, g.name, g.shape) == (nf, nr, f"{nf}x{nr}", (nr, nf + 1))
    assert len(g.fF) == nf + 1 and g.fF[0] == 0 and len(g.R) == nr
    assert g.default_chunk() == chunk and sum(r.stop - r.start for _, r, c in g.blocks(chunk) if c.start == 0) == nr


@pytest.mark.parametrize("args, message", [(["--grid", "1"], "NF must be an int in [2, 4096]"),
                                           (["--grid", "8x1"], "NR must be an int in [2, 4096]"),
                                           (["--grid", "8 by 3"], "grid must be N or NFxNR"),
                                           (["--chunk", "0"], "chunk must be an int in [1, 1024]"),
                                           (["--workers", "0"], "workers must be an int in [1, 256]")])
def test_bad_input_exits_2(args, message, tmp_path, capsys):
    assert cli.main(["atlas", *args, "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not (tmp_path / "atlas.zarr").exists()


def test_a_directory_that_is_not_an_atlas_is_refused(tmp_path, capsys):
    (tmp_path / "atlas.zarr").mkdir()
    (tmp_path / "atlas.zarr" / "notes.txt").write_text("mine")
    assert cli.main(["atlas", "--grid", "3", "--out", str(tmp_path)]) == 2
    assert "is not an atlas store" in capsys.readouterr().err


def test_summary_pngs_and_report_from_the_store(atlas_dir, tmp_path):
    bounds = summarize(atlas_dir)
    data = json.loads((atlas_dir / "atlas.json").read_text())
    assert data["grid"] == "12x12" and data["points"] == N * (N + 1) and data["boundaries"] == json.loads(json.dumps(bounds))
    assert data["counts"]["x1"]["true"] == int(open_atlas(atlas_dir)["x1"].sum())
    assert all((atlas_dir / f"atlas_{c}.png").stat().st_size > 5000 for c in ALL)
    lines = sections.atlas_section(atlas_dir, tmp_path)
    assert "12 x 12 grid" in lines[0] and any(line.startswith("| x1: fold f/F = 2/pi | 0.") for line in lines)
    assert sum(line.startswith("![atlas ") for line in lines) == len(ALL)
    assert sections.atlas_section(tmp_path / "none", tmp_path)[0].startswith("No atlas in")


def test_report_draws_the_maps_from_a_bare_store(small_dir, tmp_path):
    bare = tmp_path / "bare"                               # only the store: the report draws the maps
    bare.mkdir()
    os.symlink(small_dir / "atlas.zarr", bare / "atlas.zarr")
    lines = sections.atlas_section(bare, tmp_path / "report")
    assert (tmp_path / "report" / "atlas_area-preservation.png").stat().st_size > 5000
    assert "![atlas area-preservation](atlas_area-preservation.png)" in lines
