"""mjrft sweep: grids, local worker processes, resume, the table, errors, and the Ray dispatch path."""

from __future__ import annotations

import csv
import json
import sys
import types

import pytest

import mjrft.train.sweep as sw
from mjrft.tools import cli

HEX = "mjrft/HexapodSand-v0"


def fake_run_point(calls):
    """A stand-in for run_point (same record format) that notes which points it ran."""

    def run(settings, params, role):
        calls.append(dict(params))
        return {"key": sw.point_key(params), "params": params, "status": "ok",
                "result": {m: float(sum(v for v in params.values() if isinstance(v, (int, float))))
                           for m in sw.ENV_METRICS}, "wall_s": 0.0}

    return run


def lines(path):
    return [json.loads(x) for x in path.read_text().splitlines() if x.strip()]


# ------------------------------------------------------------------ the real thing, two worker processes
def test_tiny_grid_runs_in_two_worker_processes_and_writes_the_table(tmp_path):
    out = tmp_path / "grid"
    rows = sw.sweep({"f": [1.0, 2.0], "curvature": [0.0, 40.0]}, out, env=HEX, gait="tripod", seconds=0.3,
                    workers=2, progress=None)
    assert [(r["f"], r["curvature"]) for r in rows] == [(1.0, 0.0), (1.0, 40.0), (2.0, 0.0), (2.0, 40.0)]
    assert all(r["status"] == "ok" for r in rows)
    for r in rows:
        assert r["distance_m"] == pytest.approx(r["speed_m_s"] * 0.3, rel=1e-6)
        assert r["sink_peak_mm"] > 0 and r["cot"] > 0 and r["fall_rate"] == 0
    md = (out / "table.md").read_text().splitlines()
    assert md[0] == "| f | curvature | " + " | ".join(sw.ENV_METRICS) + " |" and len(md) == 6
    with open(out / "table.csv") as fh:
        table = list(csv.DictReader(fh))
    assert len(table) == 4 and float(table[3]["distance_m"]) == pytest.approx(rows[3]["distance_m"])
    assert len(lines(out / "results.jsonl")) == 4
    settings = json.loads((out / "sweep.json").read_text())["settings"]
    assert settings == {"kind": "env", "env": HEX, "gait": "tripod", "seconds": 0.3, "episodes": 1, "seed": 0,
                        "env_kwargs": {}}

    # a rerun computes nothing (run_point must not be called) and gives the same table
    def boom(*a):
        raise AssertionError("a finished point was run again")

    sw_run = sw.run_point
    sw.run_point = boom
    try:
        again = sw.sweep({"f": [1, 2], "curvature": [0, 40]}, out, env=HEX, gait="tripod", seconds=0.3,
                         workers=2, progress=None)  # ints: the same points as the floats above
    finally:
        sw.run_point = sw_run
    assert again == rows
    assert len(lines(out / "results.jsonl")) == 4


def test_rig_grid(tmp_path):
    rows = sw.sweep({"beta": [0.0, 0.7854]}, tmp_path, rig="plate", rig_kwargs={"depth": 0.02, "step": 0.002},
                    workers=1, progress=None)
    assert [r["status"] for r in rows] == ["ok", "ok"]
    flat, tilted = rows
    assert flat["lift_peak_N"] > tilted["lift_peak_N"] > 0  # pushed straight down: a tilted plate lifts less
    assert flat["depth_max_mm"] == pytest.approx(20.0, abs=0.5)


# ------------------------------------------------------------------ resume
def test_partial_results_resume_only_the_missing_points(tmp_path, monkeypatch):
    calls = []
    monkeypatch.setattr(sw, "run_point", fake_run_point(calls))
    grid = {"f": [1, 2, 3], "duty": [0.5, 0.6]}
    sw.sweep(grid, tmp_path, env=HEX, gait="tripod", workers=1, progress=None)
    assert len(calls) == 6
    # keep two finished points and a line torn by a crash
    recs = (tmp_path / "results.jsonl").read_text().splitlines()
    (tmp_path / "results.jsonl").write_text(recs[0] + "\n" + recs[3] + "\n" + recs[4][:25])
    calls.clear()
    rows = sw.sweep(grid, tmp_path, env=HEX, gait="tripod", workers=1, progress=None)
    ran = {sw.point_key(c) for c in calls}
    kept = {json.loads(recs[i])["key"] for i in (0, 3)}
    assert len(calls) == 4 and not ran & kept
    assert all(r["status"] == "ok" for r in rows) and len(rows) == 6
    assert len(sw.read_results(tmp_path / "results.jsonl")) == 6  # the torn line was not glued to a new one
    # adding values runs only the new points
    calls.clear()
    sw.sweep({"f": [1, 2, 3, 4], "duty": [0.5, 0.6]}, tmp_path, env=HEX, gait="tripod", workers=1, progress=None)
    assert sorted(c["f"] for c in calls) == [4, 4]


def test_failed_points_are_recorded_and_retried_on_request(tmp_path):
    # f = 4 Hz needs a hip speed beyond the env's limit: the gait refuses it, the grid goes on
    rows = sw.sweep({"f": [0.5, 4.0]}, tmp_path, env=HEX, gait="tripod", seconds=0.05, workers=1, progress=None)
    assert rows[0]["status"] == "ok"
    assert rows[1]["status"] == "error" and "max_hip_speed" in rows[1]["error"]
    assert "max_hip_speed" in (tmp_path / "table.md").read_text()
    calls = []
    real = sw.run_point

    def counting(settings, params, role):
        calls.append(params)
        return real(settings, params, role)

    sw.run_point = counting
    try:
        sw.sweep({"f": [0.5, 4.0]}, tmp_path, env=HEX, gait="tripod", seconds=0.05, workers=1, progress=None)
        assert calls == []
        sw.sweep({"f": [0.5, 4.0]}, tmp_path, env=HEX, gait="tripod", seconds=0.05, workers=1, progress=None,
                 retry_errors=True)
        assert calls == [{"f": 4.0}]
    finally:
        sw.run_point = real


def test_other_settings_in_the_same_folder_are_refused(tmp_path, monkeypatch):
    monkeypatch.setattr(sw, "run_point", fake_run_point([]))
    sw.sweep({"f": [1]}, tmp_path, env=HEX, gait="tripod", seconds=1.0, workers=1, progress=None)
    with pytest.raises(ValueError, match=r"holds a sweep with other settings \(differs in: seconds"):
        sw.sweep({"f": [1]}, tmp_path, env=HEX, gait="tripod", seconds=2.0, workers=1, progress=None)


# ------------------------------------------------------------------ bad input
@pytest.mark.parametrize("items,msg", [
    (["f"], "grid axis must be NAME=V1,V2"),
    (["f="], "grid axis must be NAME=V1,V2"),
    (["1f=2"], "grid axis must be NAME=V1,V2"),
    (["f=1,2", "f=3"], "grid axis 'f' given twice"),
    (["f=1,1.0"], "lists a value twice"),
    (["f=1,,2"], "empty value"),
    (["f=1:3"], "START:STOP:COUNT"),
    (["f=1:3:1"], "START:STOP:COUNT"),
    (["f=1:x:3"], "START:STOP:COUNT"),
    (["f=nan"], "not finite"),
])
def test_bad_grid_specs(items, msg):
    with pytest.raises(ValueError, match=msg):
        sw.parse_grid(items)


def test_grid_parsing_and_points():
    grid = sw.parse_grid(["f=1:3:3", "medium=poppy_lp,glass3_cp", "gait.duty=0.5"])
    assert grid == {"f": [1.0, 2.0, 3.0], "medium": ["poppy_lp", "glass3_cp"], "gait.duty": [0.5]}
    points = sw.grid_points(grid)
    assert len(points) == 6 and points[1] == {"f": 1.0, "medium": "glass3_cp", "gait.duty": 0.5}
    assert sw.point_key({"f": 2}) == sw.point_key({"f": 2.0})
    np = pytest.importorskip("numpy")
    assert sw.check_grid({"f": np.linspace(1, 2, 3)}) == {"f": [1.0, 1.5, 2.0]}  # numpy values become Python's
    assert type(sw.check_grid({"n": [np.int64(3)]})["n"][0]) is int


@pytest.mark.parametrize("kwargs,msg", [
    ({"grid": {"stride": [1]}}, r"neither a parameter of gait 'tripod' \(f, duty.*\) nor a keyword argument.*curvature"),
    ({"grid": {"gait.curvature": [1]}}, r"gait 'tripod' has no parameter 'curvature'; valid: f, duty"),
    ({"grid": {"env.f": [1]}}, r"HexapodSand-v0 has no keyword argument 'f'; valid: .*curvature"),
    ({"grid": {"x.f": [1]}}, r"prefix must be gait\. or env\."),
    ({"grid": {"f": [1]}, "env": "mjrft/Nope-v0"}, r"unknown env id 'mjrft/Nope-v0'; valid choices: .*HexapodSand"),
    ({"grid": {"f": [1]}, "gait": "hop"}, r"neither a gait \(rect, shift, stance, stand, tripod\) nor a model zip"),
    ({"grid": {"f": [1]}, "gait": None}, "needs a gait"),
    ({"grid": {"f": [1]}, "seconds": -1}, "seconds must be finite and > 0"),
    ({"grid": {"f": [1]}, "env_kwargs": {"episode_seconds": 3}}, "set by the sweep's seconds"),
    ({"grid": {"f": [1]}, "workers": 0}, "workers must be an integer >= 1"),
    ({"grid": {}}, "at least one axis"),
    ({"grid": {"f": []}}, "has no values"),
    ({"grid": {"f": [1]}, "rig": "leg"}, "either an environment"),
    ({"grid": {"f": [1]}, "env": None, "gait": None, "rig": "wheel"}, r"unknown rig 'wheel'; valid choices: leg, plate"),
    ({"grid": {"spin": [1]}, "env": None, "gait": None, "rig": "leg"}, r"rig 'leg' has no parameter 'spin'; valid: shape, omega"),
])
def test_bad_sweeps_raise_clear_errors(tmp_path, kwargs, msg):
    kw = {"env": HEX, "gait": "tripod", "workers": 1, "progress": None}
    kw.update(kwargs)
    grid = kw.pop("grid")
    with pytest.raises(ValueError, match=msg):
        sw.sweep(grid, tmp_path, **kw)
    assert not (tmp_path / "results.jsonl").exists()


def test_cli_bad_input_is_one_line_and_status_2(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["sweep", "--env", HEX, "--gait", "tripod", "--grid", "f", "--out", str(tmp_path)])
    assert exc.value.code == 2
    assert "mjrft sweep: error: grid axis must be NAME=V1,V2" in capsys.readouterr().err


def test_cli_rig_sweep(tmp_path, capsys):
    code = cli.main(["sweep", "--rig", "plate", "--grid", "gamma=1.5708", "--out", str(tmp_path), "--workers", "1",
                     "depth=0.01", "step=0.002"])
    assert code == 0
    out = capsys.readouterr().out
    assert "| gamma | lift_peak_N | drag_peak_N | torque_peak_Nm | depth_max_mm |" in out
    assert (tmp_path / "table.csv").exists()


# ------------------------------------------------------------------ Ray
class FakeRay(types.ModuleType):
    """A minimal stand-in for the ``ray`` module: init / remote / wait / get / shutdown, tasks run when
    submitted and come back from ``wait`` in reverse order. It checks sweep's dispatch and resume
    logic against Ray's call pattern, not Ray itself."""

    def __init__(self):
        super().__init__("ray")
        self.inits, self.submitted, self.shutdowns = [], [], 0

    def init(self, address=None, **kwargs):
        self.inits.append((address, kwargs))

    def remote(self, fn):
        fake = self

        class Remote:
            def remote(self, *args):
                fake.submitted.append(args[1])
                return ("ref", fn(*args))

        return Remote()

    def wait(self, refs, num_returns=1):
        refs = list(refs)
        return refs[-num_returns:], refs[:-num_returns]

    def get(self, ref):
        assert ref[0] == "ref"
        return ref[1]

    def shutdown(self):
        self.shutdowns += 1


def test_ray_dispatch_with_a_stand_in_module(tmp_path, monkeypatch):
    fake = FakeRay()
    monkeypatch.setitem(sys.modules, "ray", fake)
    calls = []
    monkeypatch.setattr(sw, "run_point", fake_run_point(calls))
    grid = {"f": [1, 2], "curvature": [0, 10, 20]}
    rows = sw.sweep(grid, tmp_path, env=HEX, gait="tripod", address="ray://head:10001", progress=None)
    assert fake.inits == [("ray://head:10001", {"ignore_reinit_error": True})] and fake.shutdowns == 1
    assert len(fake.submitted) == 6 and all(r["status"] == "ok" for r in rows)
    assert [(r["f"], r["curvature"]) for r in rows] == [(f, c) for f in (1, 2) for c in (0, 10, 20)]  # grid order
    assert rows[4]["distance_m"] == 12.0  # the stand-in's "result" f + curvature, put in the right row
    # resume through Ray: only the new points become tasks
    fake.submitted.clear()
    sw.sweep({"f": [1, 2, 3], "curvature": [0, 10, 20]}, tmp_path, env=HEX, gait="tripod",
             address="ray://head:10001", progress=None)
    assert sorted(p["curvature"] for p in fake.submitted) == [0, 10, 20]
    assert all(p["f"] == 3 for p in fake.submitted)


def test_ray_dispatch_runs_the_real_point_function(tmp_path, monkeypatch):
    """Through the stand-in, the tasks are mjrft's own run_point on a real (tiny) rig."""
    fake = FakeRay()
    monkeypatch.setitem(sys.modules, "ray", fake)
    rows = sw.sweep({"gamma": [1.5708, 0.0]}, tmp_path, rig="plate", rig_kwargs={"depth": 0.01, "step": 0.002},
                    address="local", progress=None)
    assert fake.inits[0][0] is None  # "local": ray.init() starts a throw-away local Ray
    assert [r["status"] for r in rows] == ["ok", "ok"] and rows[0]["lift_peak_N"] > 0


def test_missing_ray_says_how_to_install(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)  # import ray -> ImportError
    with pytest.raises(ValueError, match=r'pip install "mjrft\[ray\]"'):
        sw.sweep({"f": [1]}, tmp_path, env=HEX, gait="tripod", address="ray://head:10001", progress=None)
    assert not (tmp_path / "results.jsonl").exists()


def test_real_ray_if_installed(tmp_path):
    ray = pytest.importorskip("ray")
    rows = sw.sweep({"gamma": [1.5708, 0.0]}, tmp_path, rig="plate", rig_kwargs={"depth": 0.01, "step": 0.002},
                    address="local", progress=None)
    assert [r["status"] for r in rows] == ["ok", "ok"]
    assert not ray.is_initialized()
