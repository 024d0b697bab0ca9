"""The claims atlas (``cross_check.atlas``) on a local Dask cluster: a tiny atlas, the closed-form
boundaries within one grid cell, the same numbers for 1 and 2 workers and any chunking, and
nothing lost when a worker is killed mid-run."""
import json
import os
import signal

import pytest

distributed = pytest.importorskip("distributed", reason="the atlas needs dask.distributed (the atlas extra)")

from cross_check import __main__ as cli  # noqa: E402
from cross_check.atlas import Grid, claims, compute, maps, write  # noqa: E402

N = 12


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as c:
        yield c


@pytest.fixture(scope="module")
def atlas(client):
    return compute(list(claims.CLAIMS), N, client=client)


@pytest.mark.parametrize("boundary", ["x1: fold f/F = 2/pi", "x2: w^2 R/F = sqrt(4 - pi^2 (f/F)^2)",
                                      "period 3: f/F = 2/(3 pi)", "no impact (f = 0): w^2 R/F = 2",
                                      "attractor sticks: f/F = 1/sqrt(1 + pi^2/4)"])
def test_computed_boundary_within_one_cell_of_the_closed_form(atlas, boundary):
    grid, values, _ = atlas
    worst, lines = maps.boundaries(grid, values)[boundary]
    assert lines >= 1 and worst <= 1.0, (boundary, worst, lines)


def test_dissip_violations_are_confirmed_by_the_reference(atlas):
    _, values, _ = atlas
    seen = [d for row in values["dissip-invariance"] for d in row if d["fraction"]]
    assert seen and all(d["confirmed"] for d in seen)
    assert all(len(d["counterexamples"]) >= 1 for d in seen)


def test_area_is_preserved_on_non_sticking_starts(atlas):
    _, values, _ = atlas
    dets = [d["max_det_minus_1"] for row in values["area-preservation"] for d in row if d["max_det_minus_1"] is not None]
    assert dets and max(dets) < 1e-9          # claim_unit_det


def test_same_numbers_for_one_worker_and_other_chunks(atlas):
    grid, values, _ = atlas
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as one:
        _, again, stats = compute(list(claims.CLAIMS), N, client=one, chunk=7)
    assert stats["workers"] == 1
    assert json.dumps(again, sort_keys=True) == json.dumps(values, sort_keys=True)


def test_a_killed_worker_loses_no_result(atlas, client):
    grid, values, _ = atlas
    killed = []

    def kill_one(_msg):
        if not killed:
            pid = next(iter(client.run(os.getpid).values()))
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    _, again, _ = compute(["symmetric", "no-impact"], N, client=client, chunk=3, progress=kill_one)
    assert killed
    assert again["symmetric"] == values["symmetric"] and again["no-impact"] == values["no-impact"]


def test_write_and_cli(atlas, tmp_path, capsys):
    grid, values, stats = atlas
    bounds = write(tmp_path, grid, values, stats, list(claims.CLAIMS))
    data = json.loads((tmp_path / "atlas.json").read_text())
    assert data["f_over_F"] == Grid(N).fF.tolist() and len(data["w2R_over_F"]) == N
    assert set(data["values"]) == set(claims.CLAIMS) and data["boundaries"] == json.loads(json.dumps(bounds))
    assert all((tmp_path / f"atlas_{c}.png").stat().st_size > 5000 for c in claims.CLAIMS)
    assert cli.main(["atlas", "--grid", "1"]) == 2
    assert "grid must be" in capsys.readouterr().err
