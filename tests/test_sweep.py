"""``rr.sweep``: a friction sweep in local processes and on a Dask LocalCluster,
results in the order of the parameters and each against v0²/(2 μ g); a failing run
is reported with its parameters and the others still return."""
from __future__ import annotations

import pytest

import rigidrs as rr
from sweep_runs import DT, G, V0, slide

MUS = [0.2, 0.35, 0.5, 0.65, 0.8]


def check(distances: list[float]) -> None:
    # The stop is resolved to a step: within one step's travel at launch speed.
    for mu, d in zip(MUS, distances):
        assert d == pytest.approx(V0**2 / (2 * mu * G), abs=V0 * DT), mu


def test_sweep_in_local_processes_keeps_order() -> None:
    check(rr.sweep(slide, MUS, chunksize=2, progress=False, max_workers=2))


def test_a_failed_run_is_reported_with_its_parameters_and_the_others_return(capsys: pytest.CaptureFixture[str]) -> None:
    params = [0.2, -1.0, 0.8]
    with pytest.raises(rr.SweepError, match=r"1 of 3 runs failed:\n  run 1 with params -1.0: RigidError: .*friction") as info:
        rr.sweep(slide, params, chunksize=3, max_workers=1)
    results = info.value.results
    assert isinstance(results[1], rr.SweepFailure) and results[1].params == -1.0
    assert "Traceback" in results[1].traceback
    assert results[0] == pytest.approx(slide(0.2)) and results[2] == pytest.approx(slide(0.8))
    assert "3/3" in capsys.readouterr().err  # the progress counter (or tqdm's bar) on stderr
    returned = rr.sweep(slide, params, chunksize=1, progress=False, errors="return", max_workers=2)
    assert [type(r) for r in returned] == [float, rr.SweepFailure, float]


def test_sweep_on_a_dask_cluster_keeps_order() -> None:
    distributed = pytest.importorskip("distributed")  # in the test extra; skipped only where it cannot install
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            check(rr.sweep(slide, MUS, client=client, chunksize=2, progress=False))
            out = rr.sweep(slide, [0.5, -2.0], client=client, errors="return", progress=False)
            assert out[0] == pytest.approx(slide(0.5)) and isinstance(out[1], rr.SweepFailure)
            assert out[1].index == 1 and out[1].params == -2.0


def test_bad_arguments() -> None:
    with pytest.raises(ValueError, match="errors must be"):
        rr.sweep(slide, MUS, errors="ignore")
    with pytest.raises(ValueError, match="chunksize must be a positive integer"):
        rr.sweep(slide, MUS, chunksize=0)
    assert rr.sweep(slide, [], progress=False) == []


def test_a_lambda_runs_in_processes_through_cloudpickle() -> None:
    pytest.importorskip("cloudpickle")  # comes with the dask extra (in the test extra)
    assert rr.sweep(lambda x: x * x, [1, 2, 3], progress=False, max_workers=1) == [1, 4, 9]
