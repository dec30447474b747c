"""Reading scene files: which file is read, and what any byte sequence gives.

A path with a folder part is read as given and never falls back to a shipped example (a
folder typo must not run an example under the user's title); a bare name reads a file in
the working folder first, then a shipped example, and the CLI says which on stderr. Any
bytes at all (mutated scenes, other encodings, garbage) end in a Scene or one SceneError
line, never another exception: non-UTF-8 input names the byte offset where decoding failed.
"""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from assembly.analysis.modal import solve_modes
from assembly.app.cli import main
from assembly.app.errors import user_errors
from assembly.errors import SceneError
from assembly.model.assemble import assemble
from assembly.scene.schema import SCENE_DIR, load_scene, resolve_scene_path, shipped_scenes
from tests.support.fuzz import examples

NAMES = [p.name for p in shipped_scenes()]


@pytest.mark.parametrize("name", NAMES)
def test_a_folder_typo_never_runs_a_shipped_example(name, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "my_scenes").mkdir()
    (tmp_path / "my_scenes" / name).write_bytes((SCENE_DIR / name).read_bytes())
    for typo in (f"my_scene/{name}", f"./{name}", str(tmp_path / "nope" / name)):
        with pytest.raises(SceneError, match="no such file") as err:
            resolve_scene_path(typo)
        assert repr(name) in str(err.value)          # the hint names the bare name to use
        assert main(["modes", typo]) == 2
        out = capsys.readouterr()
        assert out.out == "" and len(out.err.strip().splitlines()) == 1


def test_a_bare_name_reads_the_local_file_first_and_says_which(tmp_path, monkeypatch, capsys):
    name = "kahraman_beta0.toml"
    monkeypatch.chdir(tmp_path)
    assert main(["modes", name]) == 0
    err = capsys.readouterr().err
    assert f"{SCENE_DIR / name}" in err and "shipped example" in err
    text = (SCENE_DIR / name).read_text().replace('name = "', 'name = "local copy of ', 1)
    (tmp_path / name).write_text(text)
    assert main(["modes", name]) == 0
    out = capsys.readouterr()
    assert str(tmp_path / name) in out.err and "shipped" not in out.err
    assert "local copy of" in out.out


@pytest.mark.parametrize("codec", ["latin-1", "cp1252", "utf-16", "utf-32"])
def test_other_encodings_name_the_first_bad_byte(codec, tmp_path):
    text = (SCENE_DIR / "kahraman_beta0.toml").read_text().replace("#", "# Zahnrad Müller, 20 °C:", 1)
    raw = text.encode(codec)
    f = tmp_path / "scene.toml"
    f.write_bytes(raw)
    try:
        raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        at = exc.start
    with pytest.raises(SceneError, match=f"not UTF-8 text at byte {at} ") as err:
        load_scene(f)
    assert len(str(err.value).splitlines()) == 1


def test_utf8_with_bom_is_read(tmp_path):
    f = tmp_path / "scene.toml"
    f.write_bytes(b"\xef\xbb\xbf" + (SCENE_DIR / "kahraman_beta0.toml").read_bytes())
    assert load_scene(f).name == load_scene(SCENE_DIR / "kahraman_beta0.toml").name


def test_a_folder_or_an_empty_file_is_one_line(tmp_path):
    with pytest.raises(SceneError, match="cannot read"):
        load_scene(tmp_path)
    (tmp_path / "empty.toml").write_bytes(b"")
    with pytest.raises(SceneError):      # an empty TOML is a scene without bodies
        load_scene(tmp_path / "empty.toml")


BASE = (SCENE_DIR / "kahraman_beta20.toml").read_bytes()


@st.composite
def mutated_bytes(draw):
    """A shipped scene with a few random byte edits, or random bytes altogether."""
    if draw(st.booleans()):
        return draw(st.binary(max_size=400))
    raw = bytearray(BASE)
    for _ in range(draw(st.integers(1, 4))):
        i = draw(st.integers(0, len(raw) - 1))
        op = draw(st.sampled_from(["flip", "insert", "delete", "truncate"]))
        if op == "flip":
            raw[i] ^= 1 << draw(st.integers(0, 7))
        elif op == "insert":
            raw[i:i] = draw(st.binary(min_size=1, max_size=4))
        elif op == "delete":
            del raw[i]
        else:
            del raw[i:]
        if not raw:
            break
    return bytes(raw)


@settings(max_examples=examples(150), deadline=None)
@given(raw=mutated_bytes())
def test_any_bytes_give_a_scene_or_one_scene_error(raw, tmp_path_factory):
    """File reading fuzz: bytes -> decode -> TOML -> scene -> assembly -> modes. A scene that
    loads is solved too (12 DOFs: milliseconds). ``make fuzz`` draws more (tests/support/fuzz.py;
    CI draws the same 150 every run)."""
    f = tmp_path_factory.mktemp("fuzz") / "scene.toml"
    f.write_bytes(raw)
    try:
        res = solve_modes(assemble(load_scene(f)))
    except user_errors() as exc:
        assert len(str(exc).splitlines()) == 1, str(exc)
    else:
        assert np.all(np.isfinite(res.frequencies_hz)) and res.max_residual < 1e-8


def test_a_shipped_example_may_be_named_without_toml(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert resolve_scene_path("two_stage_quill") == SCENE_DIR / "two_stage_quill.toml"
    (tmp_path / "two_stage_quill").write_text("not a scene")   # a local file still comes first
    assert resolve_scene_path("two_stage_quill").resolve() == tmp_path / "two_stage_quill"
    with pytest.raises(SceneError, match="no such file"):
        resolve_scene_path("./no_such_example")
