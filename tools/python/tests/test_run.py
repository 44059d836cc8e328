"""mccd.run(): the `mccd run` command's work from Python (frames as files, a pattern or a
folder, or a built-in scene), its files, its per-step records, and how it stops."""
import json
import math
import os
import signal
import threading

import numpy as np
import pytest

import mccd
from conftest import read_contacts_csv


@pytest.fixture(scope="module")
def frame_files(tmp_path_factory):
    """A generated scene of one mesh written as 6 PLY frames; returns (folder, scene frames, meshes)."""
    folder = tmp_path_factory.mktemp("frames")
    meshes, frames = mccd.make_scene("cloth", 1, 6)
    V, F, _ = meshes[0]
    for k, frame in enumerate(frames):
        mccd.save_mesh(folder / f"cloth{k}.ply", frame[0], F)
    return folder, frames, meshes


def expected_steps(meshes, frames):
    scene = mccd.Scene(meshes)
    return [scene.advance(f).contacts for f in frames[1:]]


def test_files_pattern_and_folder_give_the_same_steps(frame_files, tmp_path):
    folder, frames, meshes = frame_files
    expected = expected_steps(meshes, frames)
    files = [folder / f"cloth{k}.ply" for k in range(6)]
    results = [mccd.run(files), mccd.run(str(folder / "cloth%d.ply")), mccd.run(folder, threads=1)]
    for res in results:
        assert isinstance(res, mccd.RunResult) and len(res) == 5
        s = res.steps
        assert s.dtype == mccd.RUN_STEP_DTYPE and list(s["step"]) == [0, 1, 2, 3, 4]
        for k, c in enumerate(expected):
            assert s[k]["vf"] == np.count_nonzero(c["kind"] == mccd.VERTEX_FACE)
            assert s[k]["ee"] == np.count_nonzero(c["kind"] == mccd.EDGE_EDGE)
            assert s[k]["first_impact"] == (k + c["toi"].min() if len(c) else math.inf)
            assert s[k]["seconds"] > 0
        assert res.summary["steps"] == 5
        assert res.summary["vf_contacts"] == sum(s["vf"]) and res.summary["ee_contacts"] == sum(s["ee"])
        assert res.summary["steps_with_contacts"] == np.count_nonzero(s["vf"] + s["ee"])
        assert "mccd.RunResult" in repr(res)


def test_contacts_stats_and_pictures(frame_files, tmp_path):
    folder, frames, meshes = frame_files
    expected = expected_steps(meshes, frames)
    res = mccd.run(folder, contacts=tmp_path / "c.csv", stats=tmp_path / "s.json", image=tmp_path / "first.png",
                   image_size=(160, 120), colored=tmp_path / "first.ply")
    rows = read_contacts_csv(tmp_path / "c.csv")
    assert len(rows) == sum(map(len, expected))
    for k, c in enumerate(expected):
        assert np.array_equal(rows[rows["frame"] == k]["t"], c["toi"])
    stats = json.loads((tmp_path / "s.json").read_text())
    assert stats["complete"] is True and len(stats["steps"]) == 5
    assert [s["contacts"] for s in stats["steps"]] == [len(c) for c in expected]
    assert stats["summary"]["vf_contacts"] == res.summary["vf_contacts"]
    assert (tmp_path / "first.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    V, F = mccd.load_mesh(tmp_path / "first.ply")
    assert len(F) == len(meshes[0][1])
    res = mccd.run(folder, contacts=tmp_path / "c.json")
    doc = json.loads((tmp_path / "c.json").read_text())
    assert doc["complete"] is True and len(doc["contacts"]) == len(rows)


def test_an_unreadable_frame_keeps_the_finished_steps(frame_files, tmp_path):
    folder, frames, meshes = frame_files
    broken = tmp_path / "broken"
    broken.mkdir()
    for k in range(6):
        (broken / f"cloth{k}.ply").write_bytes((folder / f"cloth{k}.ply").read_bytes())
    (broken / "cloth4.ply").write_bytes(b"ply\nformat ascii 1.0\nend_header\n")
    with pytest.raises(mccd.Error, match="cloth4.ply"):
        mccd.run(broken, contacts=tmp_path / "kept.csv")
    lines = (tmp_path / "kept.csv").read_text().splitlines()
    assert lines[-1].startswith("# incomplete: ") and "cloth4.ply" in lines[-1]
    with pytest.raises(mccd.Error, match="cloth4.ply"):
        mccd.run(broken, contacts=tmp_path / "removed.csv", partial="remove")
    assert not (tmp_path / "removed.csv").exists()
    assert not [p for p in tmp_path.iterdir() if "tmp" in p.name.lower()], "a temporary was left behind"


def test_bad_arguments(frame_files, tmp_path):
    folder, _, _ = frame_files
    cases = [
        (dict(), "no frames given"),
        (dict(frames=folder, scene="cloth"), "either frames or scene"),
        (dict(frames=folder, substeps=0), r"^substeps: 0: expected 1 to 1000$"),
        (dict(frames=folder, threads=0), r"^threads: 0"),
        (dict(frames=folder, partial="maybe"), r"^partial: 'maybe'"),
        (dict(frames=folder, method="best"), "fbd"),
        (dict(frames=folder, contacts=tmp_path / "c.txt"), r"expected a \.csv or \.json"),
        (dict(frames=folder, image=tmp_path / "no" / "such" / "dir.png"), "no such folder"),
        (dict(frames=[folder / "cloth0.ply"]), "need at least two frames"),
        (dict(frames=tmp_path / "empty%d.ply"), "empty"),
        (dict(scene="cloth", size=0), r"^size: 0: expected 1 to 200$"),
        (dict(scene="teapot", size=1, frame_count=2), "teapot|unknown"),
        (dict(frames=folder, image_size=(8, 8)), "image_size"),
    ]
    for kwargs, message in cases:
        with pytest.raises(mccd.Error, match=message):
            mccd.run(**kwargs)


@pytest.mark.parametrize("threads", [1, 2])
def test_ctrl_c_stops_the_run_and_keeps_the_finished_steps(tmp_path, threads):
    """SIGINT during a long run: KeyboardInterrupt after the current step, the contacts file
    keeping the finished steps, marked incomplete."""
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            # 39 steps of 1,000 sub-steps each, a tenth of a second or more per step: the signal
            # comes during the first few
            mccd.run(scene="cloth", size=2, frame_count=40, substeps=1000, threads=threads,
                     contacts=tmp_path / "c.csv")
    finally:
        timer.cancel()
    lines = (tmp_path / "c.csv").read_text().splitlines()
    assert lines[0].startswith("frame,substep,kind")
    assert lines[-1] == "# incomplete: KeyboardInterrupt"
    frames = [int(line.split(",")[0]) for line in lines[1:-1]]
    assert frames == sorted(frames) and (not frames or frames[-1] < 38), "the run did not stop"
