"""Fuzz OpenFAST output files as a run reads them (``openfast = FILE`` of a load or of the
generator): malformed files of every kind, through the Python API and the command line.

Classes (seeded generator; tests/support/openfast_files.py writes the valid files each case
starts from: binary FileFmtID 1-4, OpenFAST text in UTF-8, FAST v7 text in Windows-1252):
truncated binary (at a sampled byte of every header field and of the data), wrong FileFmtID,
channel and time counts off by one, non-monotonic time (packed times swapped, TimeIncr <= 0,
rows swapped), NaN rows (text NaN, float64 NaN, ColScl NaN / 0 / inf), missing columns,
unknown units, a channel of another kind (GenPwr as a torque), control characters in names,
empty files, wrong encodings (UTF-16, bytes that are neither UTF-8 nor Windows-1252), and
random byte flips. A malformed file is refused by one SceneError line naming
``simulation.loads[0].openfast`` (or ``.column``); exit code 2 on the command line, never a
traceback. Byte flips and truncated text may leave a valid file: then the run completes
with finite histories."""
from __future__ import annotations

import io
import math
import random
from contextlib import redirect_stderr, redirect_stdout

import numpy as np
import pytest

from assembly.app.cli import main
from assembly.dynamics.simulate import simulate
from assembly.errors import SceneError
from assembly.model.assemble import assemble
from assembly.scene.schema import scene_from_dict
from tests.hard_cases.test_fuzz_time_domain import scene
from tests.support.fuzz import examples
from tests.support.openfast_files import FAST7_HEADER, out_text, outb_bytes

NAMES = ["Time", "GenTq", "GenPwr", "RotSpeed"]
UNITS = ["(s)", "(kN-m)", "(kW)", "(rpm)"]
FIELDS = ("simulation.loads[0].openfast = ", "simulation.loads[0].column = ")


def scene_dict(name: str, column: str) -> dict:
    """The torsional pair of test_fuzz_time_domain, its rotor loaded by channel ``column`` of ``name``."""
    return scene({}, {"loads": [{"body": "a", "openfast": name, "column": column}]})


def _data(nt=12):
    t = np.arange(nt) * 0.0002
    return t, np.column_stack([0.01 + 0.002 * np.sin(400 * t), 5.0 + t, 1000.0 + 0.0 * t])


def valid_files() -> dict:
    """name -> (file name, bytes) of the valid files the cases start from."""
    t, d = _data()
    out = {f"fmt{k}": (f"run{k}.outb", outb_bytes(NAMES, UNITS, t, d, k)) for k in (1, 2, 3, 4)}
    rows = [(float(a), *map(float, b)) for a, b in zip(t, d)]
    out["text"] = ("run.out", out_text(NAMES, UNITS, rows).encode("utf-8"))
    out["fast7"] = ("run7.out", out_text(NAMES, ["(sec)", "(kN·m)", "(kW)", "(rpm)"], rows, header=FAST7_HEADER,
                                         delim="  ").encode("cp1252"))
    return out


def _header_offsets(fid: int, nch: int = 3) -> list[int]:
    """Byte offsets inside each header field of a binary file of ``fid`` (module notes)."""
    pos, out = 2, [1]
    if fid == 4:
        out.append(3)
        pos = 4
    out += [pos + 2, pos + 6]                                   # NumOutChans, NT
    pos += 8
    out += [pos + 4, pos + 12]                                  # time scaling
    pos += 16
    if fid != 3:
        out += [pos + 2, pos + 4 * nch + 2]                     # ColScl, ColOff
        pos += 8 * nch
    return out + [pos + 2, pos + 6]                            # LenDesc, description


def _set(raw: bytes, at: int, value: bytes) -> bytes:
    return raw[:at] + value + raw[at + len(value):]


def cases() -> list:
    """(id, file name, bytes, column, must_refuse)."""
    rng = random.Random(26)
    files = valid_files()
    out = []

    def add(cid, name, raw, column="GenTq", refuse=True):
        out.append((cid, name, raw, column, refuse))

    for key, (name, raw) in files.items():
        add(f"{key}-valid", name, raw, refuse=False)
        add(f"{key}-missing-column", name, raw, column="GenTorque")
        add(f"{key}-power-as-torque", name, raw, column="GenPwr")
        add(f"{key}-speed-as-torque", name, raw, column="RotSpeed")
        add(f"{key}-empty", name, b"")
        add(f"{key}-blank", name, b"\n \n\t\n")
        if key.startswith("fmt"):
            fid = int(key[3:])
            desc_end = len(raw) - 3 * 12 * (8 if fid == 3 else 2) - (48 if fid == 1 else 0)
            offsets = _header_offsets(fid) + [desc_end + 1, desc_end + 20, len(raw) - 1]
            offsets += [rng.randrange(1, len(raw)) for _ in range(examples(4))]
            for at in sorted(set(offsets)):
                add(f"{key}-truncated-{at}", name, raw[:at])
            add(f"{key}-trailing-bytes", name, raw + b"\x00\x00")
            for wrong in (0, 5, 7, -1, 300, *(k for k in (1, 2, 3, 4) if k != fid)):
                add(f"{key}-fileid-{wrong}", name, _set(raw, 0, int(wrong).to_bytes(2, "little", signed=True)))
            base = 4 if fid == 4 else 2
            n_ch, nt = (int.from_bytes(raw[base + i:base + i + 4], "little") for i in (0, 4))
            for d in (-1, 1):
                add(f"{key}-channels{d:+d}", name, _set(raw, base, (n_ch + d).to_bytes(4, "little", signed=True)))
                add(f"{key}-times{d:+d}", name, _set(raw, base + 4, (nt + d).to_bytes(4, "little", signed=True)))
            add(f"{key}-negative-count", name, _set(raw, base, (-3).to_bytes(4, "little", signed=True)))
            if fid == 4:
                add(f"{key}-lenname-0", name, _set(raw, 2, (0).to_bytes(2, "little")))
            t_at = base + 8
            if fid == 1:                                       # packed times swapped
                at = len(raw) - 12 * 3 * 2 - 12 * 4
                a, b = raw[at + 12:at + 16], raw[at + 16:at + 20]
                add(f"{key}-time-swapped", name, raw[:at + 12] + b + a + raw[at + 20:])
            else:
                for incr in (0.0, -0.0002, math.nan, math.inf):
                    add(f"{key}-timeincr-{incr}", name, _set(raw, t_at + 8, np.float64(incr).tobytes()))
            if fid == 3:                                       # a NaN in GenTq's fifth row
                at = len(raw) - 12 * 3 * 8 + (4 * 3 + 0) * 8
                add(f"{key}-nan-row", name, _set(raw, at, np.float64(math.nan).tobytes()))
            else:
                for bad in (math.nan, 0.0, math.inf):          # GenTq's ColScl
                    add(f"{key}-colscl-{bad}", name, _set(raw, t_at + 16, np.float32(bad).tobytes()))
            units_at = raw.index(b"(kN-m)")
            add(f"{key}-unknown-unit", name, _set(raw, units_at, b"(lbf-ft)"[:6] + b")"))
            add(f"{key}-control-char", name, _set(raw, raw.index(b"GenTq"), b"Gen\x07q"))
            add(f"{key}-named-out", name.replace(".outb", ".out"), raw, refuse=False)   # content decides
            for k in range(examples(4)):                       # random flips: refused or a valid run
                flipped = bytearray(raw)
                for _ in range(rng.randint(1, 4)):
                    flipped[rng.randrange(len(raw))] ^= 1 << rng.randrange(8)
                add(f"{key}-flip-{k}", name, bytes(flipped), refuse=None)
        else:
            text = raw.decode("utf-8" if key == "text" else "cp1252")
            lines = text.splitlines(keepends=True)
            enc = "utf-8" if key == "text" else "cp1252"
            swapped = lines[:-3] + [lines[-2], lines[-3], lines[-1]]
            add(f"{key}-rows-swapped", name, "".join(swapped).encode(enc))
            nan = lines[:-1] + [lines[-1].replace(lines[-1].split()[1], "NaN", 1)]
            add(f"{key}-nan-row", name, "".join(nan).encode(enc))
            add(f"{key}-short-row", name, "".join(lines[:-1] + [" ".join(lines[-1].split()[:2]) + "\n"]).encode(enc))
            add(f"{key}-text-cell", name, "".join(lines[:-1] + [lines[-1].replace(lines[-1].split()[1], "x1", 1)])
                .encode(enc))
            add(f"{key}-unknown-unit", name, text.replace("(kN-m)", "(lbf-ft)").replace("(kN·m)", "(lbf-ft)")
                .encode(enc))
            add(f"{key}-no-unit-line", name, "".join(ln for ln in lines if not ln.startswith("(")).encode(enc))
            add(f"{key}-units-short", name, text.replace("(rpm)", "").encode(enc))
            add(f"{key}-utf16", name, text.encode("utf-16"))
            add(f"{key}-not-cp1252", name, raw.replace(b"Time", b"Time\x81", 1))
            add(f"{key}-header-only", name, "".join(lines[:-12]).encode(enc))
            for k in range(examples(3)):                       # cut anywhere: fewer rows, or a bad last row
                add(f"{key}-cut-{k}", name, raw[:rng.randrange(1, len(raw))], refuse=None)
    return out


CASES = cases()


@pytest.fixture(scope="module")
def model():
    return assemble(scene_from_dict(scene_dict("run.out", "GenTq")))


def _check_refusal(msg: str, cid: str):
    assert "\n" not in msg and msg.startswith(FIELDS), (cid, msg)


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_openfast_file_refused_or_run_python_api(tmp_path, model, case):
    cid, name, raw, column, refuse = case
    (tmp_path / name).write_bytes(raw)
    s = scene_from_dict(scene_dict(name, column))
    try:
        r = simulate(model, 0.002, 2e-4, ["force:m"], simulation=s.simulation, base_dir=tmp_path)
    except SceneError as exc:
        assert refuse is not False, (cid, str(exc))
        _check_refusal(str(exc), cid)
        return
    assert refuse is not True, f"{cid}: accepted"
    assert r.complete and np.all(np.isfinite(r.outputs["force:m"]))


CLI_CASES = [c for i, c in enumerate(CASES) if c[4] is True and i % 3 == 0] + [c for c in CASES if "valid" in c[0]]


@pytest.mark.parametrize("case", CLI_CASES, ids=[c[0] for c in CLI_CASES])
def test_openfast_file_refused_or_run_cli(tmp_path, case):
    cid, name, raw, column, refuse = case
    (tmp_path / name).write_bytes(raw)
    scene = tmp_path / "fuzz.toml"
    d = scene_dict(name, column)
    scene.write_text(_toml(d), encoding="utf-8")
    err, out = io.StringIO(), io.StringIO()
    with redirect_stderr(err), redirect_stdout(out):
        code = main(["simulate", str(scene), "--t-end", "0.002", "--dt", "2e-4", "--output", "force:m", "--json",
                     "-q"])
    if refuse:
        assert code == 2, (cid, err.getvalue())
        lines = err.getvalue().strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith(tuple("flexgear: error: " + f for f in FIELDS)), (cid, lines)
    else:
        assert code == 0, (cid, err.getvalue())


def _toml(d: dict) -> str:
    """The fuzz scene as TOML (flat tables and arrays of tables only)."""
    def val(v):
        if isinstance(v, str):
            return '"' + v + '"'
        if isinstance(v, list):
            return "[" + ", ".join(val(x) for x in v) + "]"
        return repr(v)
    lines = [f'name = "{d["name"]}"']
    for key in ("bodies", "meshes"):
        for item in d[key]:
            lines.append(f"[[{key}]]")
            lines += [f"{k} = {val(v)}" for k, v in item.items()]
    sim = d["simulation"]
    lines += ["[simulation]", f"speed = {sim['speed']!r}"]
    for ld in sim["loads"]:
        lines.append("[[simulation.loads]]")
        lines += [f"{k} = {val(v)}" for k, v in ld.items()]
    return "\n".join(lines) + "\n"
