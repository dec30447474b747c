"""A controller library with the Bladed-style DISCON interface, as OpenFAST's ServoDyn calls it:
``DISCON(avrSWAP, aviFAIL, accINFILE, avcOUTNAME, avcMSG)``, ``avrSWAP`` a float32 swap array
(1-based record numbers below), ``aviFAIL`` 0 for success, > 0 a warning, < 0 a failure whose
message is in ``avcMSG``.

Records written before a call (the ones ROSCO reads): 1 status (0 first call, 1 later, -1
last), 2 time (s), 3 the controller's sample period (s), 4/33/34 blade pitch angles (rad), 15
electrical power (W), 20 generator speed (rad/s), 21 rotor speed (rad/s), 23 measured generator
torque (N m), 27 hub-height wind speed (m/s), 49/50/51 the lengths of the message, input-file
and output-name buffers (with their terminating NUL), 61 number of blades, 129 the array's
size. Read back: 45 the collective pitch demand (rad), 42-44 the blades' demands, 47 the
generator torque demand (N m).

A library keeps its state in the process (Fortran SAVE variables): each :class:`Discon` loads a
private copy of the library file, so two controllers in one process do not share it. A
missing or unreadable input file is refused before the call, and so is a file the input names
that is not there (ROSCO's ``PerfFileName``, and ``OL_Filename`` when ``OL_Mode`` reads it): ROSCO's
Fortran runtime ends the whole process on a file it cannot open.

What a library prints (ROSCO's banner, its warnings and status lines) goes to the file
``controller.log`` in its folder, not to the user's terminal: the process's standard output is
pointed there for the length of each call, with the Fortran runtime's preconnected units
unbuffered (``GFORTRAN_UNBUFFERED_PRECONNECTED``, read when the runtime loads) so that nothing
it wrote is flushed after the call; :attr:`Discon.log_file` names it.
"""
from __future__ import annotations

import ctypes
import logging
import math
import os
import shutil
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import SceneError
from .openfast_deck import input_entry

log = logging.getLogger(__name__)

#: Size of the swap array (ServoDyn's default is enough for ROSCO's records up to 1018)
SWAP_SIZE = 3000
MESSAGE_SIZE = 1024


#: ROSCO's input keys that name a file it opens (relative to the input file), with the mode key
#: that makes it read the file (None: always).
INPUT_FILES = {"PerfFileName": None, "OL_Filename": "OL_Mode"}


def named_files(text: str) -> dict:
    """{key: file name} of the files a ROSCO-style input names and will open (module notes):
    ``"name"  ! Key`` lines of :data:`INPUT_FILES`, those of a mode key set to 0 or "unused" left out."""
    values = dict(e for e in (input_entry(line, True) for line in text.splitlines()) if e is not None)
    out = {}
    for key, mode in INPUT_FILES.items():
        name = values.get(key)
        if name is None or name.strip().lower() in ("", "unused"):
            continue
        if mode is not None and values.get(mode, "0").strip() in ("0", "0.0"):
            continue
        out[key] = name
    return out


class ControllerError(SceneError):
    """The library refused a call (``aviFAIL`` < 0) or returned a value that is not finite."""


@dataclass(frozen=True)
class DisconOutput:
    """A call's demands: ``generator_torque`` (N m), ``pitch`` (rad, collective) and the
    ``blade_pitch`` (3,) demands (rad)."""

    generator_torque: float
    pitch: float
    blade_pitch: tuple


class Discon:
    """The library ``library`` with its input file ``infile`` (module notes); ``field`` names
    them in errors; ``workdir`` takes the library's own output files (default: a temporary
    folder, removed by :meth:`close`)."""

    def __init__(self, library, infile, field: str = "turbine.controller", workdir=None):
        self.field = field
        lib, inp = Path(library), Path(infile)
        for name, p in (("library", lib), ("input", inp)):
            if not p.is_file():
                raise SceneError(f"{field}.{name}", str(p), "is not a file")
        try:
            text = inp.read_bytes().decode("latin-1")
        except OSError as exc:
            raise SceneError(f"{field}.input", str(inp), f"cannot be read ({exc.strerror})") from None
        for key, name in named_files(text).items():
            if not (inp.parent / name).is_file():
                raise SceneError(f"{field}.input", str(inp), f"names {key} = {name!r}, which is not a file "
                                                             f"({inp.parent / name}); the library would end the "
                                                             f"process on it")
        self._tmp = Path(tempfile.mkdtemp(prefix="flexgear-discon-"))
        private = self._tmp / lib.name
        shutil.copyfile(lib, private)                       # this controller's own state
        os.environ.setdefault("GFORTRAN_UNBUFFERED_PRECONNECTED", "y")
        try:
            # the library as installed first: the libraries it needs (a wheel's bundled Fortran
            # runtime, found relative to its own folder) are then loaded, and the private copy's
            # needs resolve to them by name
            ctypes.CDLL(str(lib.resolve()))
            self._fn = ctypes.CDLL(str(private)).DISCON
        except (OSError, AttributeError) as exc:
            shutil.rmtree(self._tmp, ignore_errors=True)
            raise SceneError(f"{field}.library", str(lib), f"cannot be loaded as a DISCON library "
                                                           f"({type(exc).__name__}: {exc})") from None
        self._fn.restype = None
        self._fn.argtypes = [ctypes.POINTER(ctypes.c_float), ctypes.POINTER(ctypes.c_int), ctypes.c_char_p,
                             ctypes.c_char_p, ctypes.c_char_p]
        self._infile = str(inp.resolve()).encode() + b"\0"
        # a folder of its own for the library's files: the Fortran runtime the copies share
        # refuses a file that another instance has open
        out = Path(tempfile.mkdtemp(prefix="controller-", dir=workdir)) if workdir is not None else self._tmp
        self._outname = str(out / "controller").encode() + b"\0"
        self.log_file = out / "controller.log"
        self._log = os.open(self.log_file, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o644)
        self._msg = ctypes.create_string_buffer(MESSAGE_SIZE + 1)
        self._swap = np.zeros(SWAP_SIZE, np.float32)
        self.calls = 0
        self.times: list = []

    def step(self, t: float, dt: float, generator_speed: float, rotor_speed: float, pitch, generator_torque: float,
             wind: float, power: float = 0.0) -> DisconOutput:
        """One call at time ``t`` with the measured state; the demands (module notes)."""
        sw = self._swap
        blades = np.broadcast_to(np.asarray(pitch, float), (3,))
        sw[0] = 0.0 if self.calls == 0 else 1.0
        sw[1], sw[2] = t, dt
        sw[3], sw[32], sw[33] = blades
        sw[14], sw[19], sw[20], sw[22], sw[26] = power, generator_speed, rotor_speed, generator_torque, wind
        sw[48], sw[49], sw[50] = len(self._msg) - 1, len(self._infile), len(self._outname)
        sw[60], sw[128] = 3.0, SWAP_SIZE
        fail = self._call()
        self.calls += 1
        self.times.append(t)
        out = DisconOutput(float(sw[46]), float(sw[44]), (float(sw[41]), float(sw[42]), float(sw[43])))
        if fail < 0:
            raise ControllerError(self.field, f"aviFAIL = {fail} at t = {t:g} s", self._message() or "failed")
        if fail > 0:
            log.warning("%s at t = %g s: %s", self.field, t, self._message())
        if not all(math.isfinite(x) for x in (out.generator_torque, out.pitch, *out.blade_pitch)):
            raise ControllerError(self.field, f"t = {t:g} s", f"returned demands that are not finite: {out}")
        return out

    def _call(self) -> int:
        fail = ctypes.c_int(0)
        sys.stdout.flush()
        saved = os.dup(1)
        os.dup2(self._log, 1)                               # the library's prints: its log (module notes)
        try:
            self._fn(self._swap.ctypes.data_as(ctypes.POINTER(ctypes.c_float)), ctypes.byref(fail), self._infile,
                     self._outname, self._msg)
        finally:
            os.dup2(saved, 1)
            os.close(saved)
        return fail.value

    def _message(self) -> str:
        return self._msg.value.decode(errors="replace").strip()

    def close(self) -> None:
        """The last call (status -1) if the library was called, then its files removed."""
        if self._log is None:                               # closed already
            return
        if self.calls:
            self._swap[0] = -1.0
            self._call()
        os.close(self._log)
        self._log = None
        shutil.rmtree(self._tmp, ignore_errors=True)
