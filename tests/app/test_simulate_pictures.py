"""What the pictures of a long run draw (:mod:`assembly.app.report.simulate`): a trace's min and
max per column, every extreme kept; a spectrum averaged over segments read in blocks, a
sinusoid of amplitude A still at A."""
from __future__ import annotations

import numpy as np

from assembly.app.report.simulate import envelope, spectrum, spectrum_blocks


def _cut(t, y, cuts):
    return [(t[a:b], y[a:b]) for a, b in zip([0, *cuts], [*cuts, len(t)])]


def test_envelope_keeps_every_columns_extremes():
    n, cols = 10_007, 50
    t = np.arange(n) * 1e-3
    y = np.sin(2 * np.pi * 3.3 * t) + np.where(np.arange(n) % 997 == 5, 4.0, 0.0)
    te, ye = envelope(_cut(t, y, [1, 333, 5000, 5001, 9000]), n, cols)
    assert len(te) == len(ye) == 2 * cols
    for c in range(cols):                         # column c: samples c n / cols to (c + 1) n / cols
        idx = np.flatnonzero((np.arange(n) * cols) // n == c)
        assert (ye[2 * c], ye[2 * c + 1]) == (y[idx].min(), y[idx].max()) and te[2 * c] == t[idx[0]]
    t_short, y_short = envelope(_cut(t[:90], y[:90], [40]), 90, cols)     # short: every sample
    assert np.array_equal(t_short, t[:90]) and np.array_equal(y_short, y[:90])


def test_segmented_spectrum_shows_a_sinusoids_amplitude():
    # A = 2.5 at 50 Hz, sampled at 1 kHz: 50 Hz is a bin of a 1024-sample segment only when
    # 50 x 1024 / 1000 is whole, so pick f on a bin (k = 64: 62.5 Hz); the Hann-windowed
    # amplitude of a sinusoid on a bin is A (spectrum's scaling)
    dt, seg, A = 1e-3, 1024, 2.5
    f0 = 64 / (seg * dt)
    t = np.arange(10 * seg + 300) * dt
    y = 1.0 + A * np.sin(2 * np.pi * f0 * t)
    f, a = spectrum_blocks(_cut(t, y, [7, 2000, 2001, 8000]), len(t), float(np.mean(y)), seg)
    k = int(np.argmax(a))
    # np.hanning is the symmetric window (period seg - 1), not the periodic one whose bins are
    # exact: the amplitude on a bin is A to O(1 / seg^2)
    assert f[k] == f0 and abs(a[k] - A) <= A / seg ** 2
    f1, a1 = spectrum_blocks(_cut(t[:seg], y[:seg], [100]), seg, 0.0, seg)   # short: the whole one's
    f2, a2 = spectrum(t[:seg], y[:seg])
    assert np.array_equal(f1, f2) and np.array_equal(a1, a2)
