"""`flexgear run`: end to end into tmp_path, index.html links, Chromium page load, atomicity."""
import csv
import json
import os
import re
import shutil
import subprocess
import sys

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

import pytest

from assembly.app.cli import build_parser
from assembly.app.output import MANIFEST, OutputDirError
from assembly.app.report.html import local_references, missing_references
from assembly.app.report.links import folder_problems
from assembly.app.report.pipeline import RunOptions, run_pipeline

SCENE = "lin_parker_n4.toml"
N_IMAGES = 3
SIZE = (480, 360)


def _parser():
    return build_parser()


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "results"
    ctx = run_pipeline(SCENE, out, RunOptions(n_modes=N_IMAGES, window_size=SIZE))
    return out, ctx


def _leftovers(parent, name):
    return [p for p in parent.iterdir() if p.name.startswith(f".{name}.")]


def test_run_writes_everything(run_dir):
    out, ctx = run_dir
    for f in ("modes.csv", "modes.json", "modes_table.txt", "fidelity_comparison.csv", "index.html", MANIFEST,
              "images/overview.png", "plots/frequencies_by_fidelity.png"):
        assert (out / f).is_file(), f
    imgs = sorted((out / "images").glob("mode_*.png"))
    assert len(imgs) == N_IMAGES
    # First elastic modes: lin_parker_n4 has one rigid-body mode (mode 1).
    assert [p.name for p in imgs] == ["mode_002.png", "mode_003.png", "mode_004.png"]
    data = json.loads((out / "modes.json").read_text())
    rows = list(csv.DictReader(open(out / "modes.csv")))
    assert len(rows) == len(data["frequencies_hz"]) == 21
    assert [float(r["frequency_hz"]) for r in rows] == pytest.approx(data["frequencies_hz"], rel=1e-8)
    assert not _leftovers(out.parent, out.name)


def test_energy_by_mode_csv_and_scope_column(run_dir):
    out, _ = run_dir
    rows = list(csv.DictReader(open(out / "energy_by_mode.csv")))
    # lin_parker_n4: one stage, 21 modes; one row per mode for the stage and for each body
    # and spring: shares of a whole sum to 1 per mode (stage rows; part rows), to the 6
    # significant digits the CSV keeps (about 30 rows of <= 5e-7 rounding each: 1e-5).
    sums = {}
    for r in rows:
        key = (r["mode"], "stage" if r["level"] == "stage" else "part")
        k, s = sums.get(key, (0.0, 0.0))
        sums[key] = (k + float(r["kinetic_share"]), s + float(r["strain_share"]))
    assert {m for m, _ in sums} == {str(i) for i in range(1, 22)}
    for (mode, _), (k, s) in sums.items():
        assert k == pytest.approx(1.0, rel=1e-5)
        assert s == pytest.approx(0.0 if mode == "1" else 1.0, abs=1e-5)   # mode 1: rigid-body
    assert {r["level"] for r in rows} == {"stage", "body", "bearing", "mesh"}
    assert {r["scope"] for r in rows} == {"stage"}   # a single stage holds every mode
    modes = list(csv.DictReader(open(out / "modes.csv")))
    assert all(r["scope"] == "stage" for r in modes)
    html = (out / "index.html").read_text()
    assert "<th class=\"l\">scope</th>" in html and "stage 100/100" in html


def test_fidelity_comparison_csv(run_dir):
    out, _ = run_dir
    rows = list(csv.DictReader(open(out / "fidelity_comparison.csv")))
    paired = [r for r in rows if r["torsional"]]
    # Torsional model of the stage: 7 modes, 1 rigid-body -> 6 elastic, each paired once.
    assert len(paired) == 6
    assert len({r["mode"] for r in rows}) == len(rows)
    for r in paired:
        assert 0.0 <= float(r["mac_torsional"]) <= 1.0 + 1e-9
        assert r["class"] and r["dominant_body"].startswith("stage.")
    # Every elastic rigid-model mode (21 DOFs, 1 rigid-body) appears once.
    assert len(rows) == 20


def test_index_references_exist(run_dir):
    out, _ = run_dir
    text = (out / "index.html").read_text()
    refs = local_references(text)
    assert "images/overview.png" in refs and "fidelity_comparison.csv" in refs
    assert missing_references(out / "index.html") == []
    assert all(not os.path.isabs(r) and ".." not in r for r in refs)
    # modes, overview, stage-local mode, fidelity plot and the animations (RunOptions.animated_modes of the
    # N_IMAGES drawn modes, all in the band)
    assert len(re.findall(r"<img ", text)) == N_IMAGES + 3 + min(N_IMAGES, RunOptions.animated_modes)
    assert "Fidelity comparison" in text and "Hz" in text
    # In-page links from the mode table land on figures that exist; the navigation's on sections.
    anchors = re.findall(r'href="#([^"]+)"', text)
    assert len([a for a in anchors if a.startswith("fig-mode-")]) == N_IMAGES
    assert all(f'id="{a}"' in text for a in anchors)
    assert folder_problems(out) == []      # the shared style, the navigation, every link and anchor


def _chromium():
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if exe:
        return exe, ""
    if hasattr(os, "geteuid") and os.geteuid() == 0 and shutil.which("apt-get"):
        env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
        try:
            subprocess.run(["apt-get", "update", "-qq"], check=True, capture_output=True, timeout=300, env=env)
            subprocess.run(["apt-get", "install", "-y", "-qq", "chromium"], check=True, capture_output=True,
                           timeout=900, env=env)
        except (subprocess.SubprocessError, OSError) as exc:
            return None, f"could not install chromium with apt-get: {exc}"
        exe = shutil.which("chromium")
        return exe, "" if exe else "apt-get install chromium gave no chromium binary"
    return None, "chromium not installed and cannot install it (needs root and apt-get)"


CHECK_SCRIPT = """<script>window.addEventListener("load", function () {
  var im = Array.from(document.images);
  var ok = im.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length;
  document.body.setAttribute("data-decoded", ok + "/" + im.length);
});</script></body>"""


@pytest.mark.slow
def test_index_loads_in_headless_chromium(run_dir, tmp_path):
    exe, why = _chromium()
    if exe is None:
        print(f"SKIP reason: {why}")
        pytest.skip(why)
    out, _ = run_dir
    copy = tmp_path / "site"
    shutil.copytree(out, copy)
    # Same page, plus a script that counts the decoded images after window.onload.
    page = copy / "_check.html"
    page.write_text((copy / "index.html").read_text().replace("</body>", CHECK_SCRIPT))
    cmd = [exe, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
           "--disable-background-networking", "--disable-component-update", "--disable-sync",
           f"--user-data-dir={tmp_path / 'profile'}", "--virtual-time-budget=15000", "--dump-dom",
           page.as_uri()]
    dom = subprocess.run(cmd, capture_output=True, text=True, timeout=120).stdout
    m = re.search(r'data-decoded="(\d+)/(\d+)"', dom)
    assert m, dom[-2000:]
    # modes, overview, stage-local mode, fidelity plot, animations (GIFs decode as images)
    assert int(m.group(2)) == N_IMAGES + 3 + min(N_IMAGES, RunOptions.animated_modes)
    assert m.group(1) == m.group(2), f"only {m.group(1)} of {m.group(2)} images decoded"


def test_cli_run_quiet_and_rerun_replaces(tmp_path, capsys):
    out = tmp_path / "r"
    args = _parser().parse_args(["run", "kahraman_beta20.toml", "--out", str(out), "--modes", "1", "--quiet",
                                 "--no-images"])
    assert args.func(args) == 0
    assert capsys.readouterr().err == ""  # no progress bars when quiet
    assert (out / "index.html").is_file() and not (out / "images").exists()
    (out / "modes_table.txt").write_text("edited")   # listed in the manifest: flexgear's, replaced
    (out / "notes.txt").write_text("the user's")    # not listed: carried over (assembly.app.output)
    assert args.func(args) == 0
    assert (out / "modes_table.txt").read_text() != "edited"
    assert (out / "notes.txt").read_text() == "the user's"
    assert not _leftovers(tmp_path, "r")


def test_bad_scene_leaves_no_output(tmp_path):
    from assembly.errors import SceneError

    bad = tmp_path / "bad.toml"
    bad.write_text('[[bodies]]\nname = "a"\nmass = -1.0\npolar_inertia = 1.0\n')
    out = tmp_path / "out"
    with pytest.raises(SceneError):
        run_pipeline(bad, out, RunOptions(n_modes=1, window_size=SIZE))
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]


def test_failure_in_a_late_step_leaves_previous_result(tmp_path):
    from assembly.app.report.pipeline import DEFAULT_STEPS, Step

    out = tmp_path / "keep"
    run_pipeline("peeters_parallel_torsional.toml", out, RunOptions(n_modes=1, images=False))
    before = sorted(p.name for p in out.iterdir())

    def boom(ctx, bar):
        raise RuntimeError("late failure")

    steps = DEFAULT_STEPS[:-1] + [Step("boom", boom)]
    with pytest.raises(RuntimeError):
        run_pipeline("kahraman_beta20.toml", out, RunOptions(n_modes=1, images=False), steps=steps)
    assert sorted(p.name for p in out.iterdir()) == before
    assert json.loads((out / MANIFEST).read_text())["scene_source"] == "peeters_parallel_torsional.toml"
    assert not _leftovers(tmp_path, "keep")


def test_refuses_foreign_folder(tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "thesis.tex").write_text("precious")
    with pytest.raises(OutputDirError):
        run_pipeline("kahraman_beta20.toml", out, RunOptions(images=False))
    assert (out / "thesis.tex").read_text() == "precious"
    from assembly.app.cli import main
    assert main(["run", "kahraman_beta20.toml", "--out", str(out), "-q"]) == 2
    assert (out / "thesis.tex").read_text() == "precious"


def test_cli_subprocess_bad_scene_exit_code(tmp_path):
    """Through the real entry point: a SceneError ends in one line, exit 2, no folder."""
    code = "import sys; from assembly.app.cli import main; sys.exit(main(sys.argv[1:]))"
    out = tmp_path / "o"
    r = subprocess.run([sys.executable, "-c", code, "run", str(tmp_path / "nope.toml"), "--out", str(out)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and "nope.toml" in r.stderr
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_the_run_writes_its_gear_table(run_dir):
    # Lin & Parker's stage: its sun-planet and planet-ring rows, the base radii the scene gives
    # (gears.csv: every field of assembly.analysis.gear_table, SI)
    from assembly.scene.schema import load_scene
    out, _ = run_dir
    rows = list(csv.DictReader(open(out / "gears.csv", encoding="utf-8")))
    st = load_scene(SCENE).stages[0]
    assert len(rows) == 2 and {int(r["count"]) for r in rows} == {st.planets.count}
    sun = next(r for r in rows if r["gear1"].endswith("sun"))
    assert float(sun["base_radius1"]) == pytest.approx(st.sun.base_radius, rel=1e-15)


def test_the_run_animates_its_first_modes_in_the_band(run_dir):
    # lin_parker_n4: one rigid-body mode, every elastic mode in the band; the first
    # RunOptions.animated_modes drawn modes get a GIF, shown under "Mode animations" and listed
    # in the manifest
    from PIL import Image

    from assembly.app.render.animation import FRAMES
    out, ctx = run_dir
    rels = [f"animations/mode_{k:03d}_anim.gif" for k in range(2, 2 + min(N_IMAGES, RunOptions.animated_modes))]
    assert [rel for rel, _, _ in ctx.animations] == rels
    text = (out / "index.html").read_text()
    section = text[text.index(">Mode animations</h2>"):]
    manifest = json.loads((out / MANIFEST).read_text())
    for rel in rels:
        assert f'<img src="{rel}"' in section and rel in manifest["files"]
        with Image.open(out / rel) as im:
            assert im.n_frames == FRAMES
    assert sorted(p.relative_to(out).as_posix() for p in (out / "animations").iterdir()) == rels
    assert manifest["options"]["animated_modes"] == RunOptions.animated_modes
