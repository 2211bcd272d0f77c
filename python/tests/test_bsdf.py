"""BSDFs over arrays: the vectorised calls equal the per-direction ones, sampling follows the pdf
(chi-square), and eval releases the GIL so that Python threads run in parallel."""
import math
import threading
import time

import numpy as np
import pytest

import glintscope
from conftest import unit


def hemisphere_directions(n, seed):
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d[:, 2] = np.abs(d[:, 2]) + 0.05
    return unit(d)


@pytest.mark.parametrize("method", ["fft", "stam", "geometric"])
def test_arrays_equal_one_direction_at_a_time(surface, method):
    bsdf = glintscope.bsdf(surface, method, res=24, sigma_c=5, lambda_=(0.45, 0.6))
    # Four incident directions (a table each for the image-based methods), ten wo each.
    wi, wo = np.repeat(hemisphere_directions(4, 1), 10, axis=0), hemisphere_directions(40, 2)
    f = bsdf.eval(wi, wo)
    p = bsdf.pdf(wi, wo)
    assert f.shape == (40, 2) and p.shape == (40,)
    for k in range(40):
        assert np.array_equal(f[k], bsdf.eval(wi[k], wo[k]))
        assert p[k] == bsdf.pdf(wi[k], wo[k])
    # Broadcasting: one wi against a grid of wo.
    grid = bsdf.eval(wi[0], wo.reshape(5, 8, 3))
    assert grid.shape == (5, 8, 2) and np.array_equal(grid.reshape(40, 2), bsdf.eval(wi[0], wo))
    # Sampling: the returned pdf is pdf(), the weight f cos(theta_o) / pdf.
    u = np.random.default_rng(3).random((40, 2))
    directions, pdfs, weights = bsdf.sample(wi, u)
    found = pdfs > 0
    assert np.allclose(pdfs[found], bsdf.pdf(wi[found], directions[found]), rtol=1e-9)
    expected = bsdf.eval(wi[found], directions[found]) * directions[found, 2:3] / pdfs[found, None]
    assert np.allclose(weights[found], expected, rtol=1e-9)
    assert np.array_equal(bsdf.albedo(wi[9:11])[1], bsdf.albedo(wi[10]))
    # Below the horizon: f = 0 and pdf = 0 (docs/renderer.md).
    assert np.all(bsdf.eval(wi[0], wo * [1, 1, -1]) == 0) and np.all(bsdf.pdf(wi[0], wo * [1, 1, -1]) == 0)


def chi_square_p_value(observed, expected):
    """Pearson's statistic, cells expecting fewer than 5 pooled; Wilson-Hilferty upper tail."""
    small = expected < 5
    obs = np.append(observed[~small], observed[small].sum())
    exp = np.append(expected[~small], expected[small].sum())
    keep = exp > 0
    statistic = np.sum((obs[keep] - exp[keep]) ** 2 / exp[keep])
    dof = keep.sum() - 1
    c = 2.0 / (9.0 * dof)
    z = ((statistic / dof) ** (1 / 3) - (1 - c)) / math.sqrt(c)
    return 0.5 * math.erfc(z / math.sqrt(2))


def test_samples_follow_the_pdf(surface):
    # As tests/lib/bsdf/conformance_test.cpp: samples binned on a grid of the projected disk against
    # the pdf integrated over each cell (dA = cos(theta_o) d(omega), so P = integral of pdf / cos).
    # stam samples its images as fft does, but its weight's eval is its closed form (fft's is the
    # point evaluation of eq. 6, which would cost most of the test).
    bsdf = glintscope.bsdf(surface, "stam", res=16, sigma_c=5)
    wi = np.array([math.sin(math.radians(30)), 0.0, math.cos(math.radians(30))])
    n, cells, sub = 200_000, 16, 8
    directions, pdfs, _ = bsdf.sample(wi, np.random.default_rng(7).random((n, 2)))
    assert np.all(pdfs > 0)
    col = np.clip(((directions[:, 0] + 1) / 2 * cells).astype(int), 0, cells - 1)
    row = np.clip(((directions[:, 1] + 1) / 2 * cells).astype(int), 0, cells - 1)
    observed = np.bincount(row * cells + col, minlength=cells * cells).astype(float)
    t = (np.arange(cells * sub) + 0.5) / (cells * sub) * 2 - 1
    x, y = np.meshgrid(t, t)
    r2 = x ** 2 + y ** 2
    inside = r2 < 1
    z = np.sqrt(np.where(inside, 1 - r2, 1))
    wo = np.stack([x, y, z], axis=-1)
    density = np.where(inside, bsdf.pdf(wi, wo) / z, 0.0) * (2 / (cells * sub)) ** 2
    expected = density.reshape(cells, sub, cells, sub).sum(axis=(1, 3)).ravel()
    assert expected.sum() == pytest.approx(1.0, abs=2e-3)
    assert chi_square_p_value(observed, expected * n) > 1e-3


def test_eval_releases_the_gil(surface):
    # Two Python threads call eval at once while this thread keeps running Python. With the GIL
    # held through an eval, this thread would stall for the whole call (the longest gap between its
    # steps ~ the evals' time: 0.96 measured for sorted(), which holds it); released, it stalls only
    # for scheduler slices. A wall-time speed-up would be the same fact, but is not robust on a
    # machine that other builds load beyond its two cores (docs/performance.md).
    bsdf = glintscope.bsdf(surface, "stam", res=24, sigma_c=5)
    wi, wo = hemisphere_directions(1, 4)[0], hemisphere_directions(100_000, 5)
    spans = []

    def evaluate():
        with glintscope.using_threads(1):  # each call on one library thread, as a renderer's threads would call it
            start = time.perf_counter()
            bsdf.eval(wi, wo)
            spans.append((start, time.perf_counter()))

    bsdf.eval(wi, wo[:100])
    threads = [threading.Thread(target=evaluate) for _ in range(2)]
    steps = []
    for thread in threads:
        thread.start()
    while any(thread.is_alive() for thread in threads):
        steps.append(time.perf_counter())
    for thread in threads:
        thread.join()
    begin, end = min(s for s, _ in spans), max(e for _, e in spans)
    inside = [begin] + [t for t in steps if begin <= t <= end] + [end]
    assert max(np.diff(inside)) / (end - begin) < 0.8


def test_eval_at_chosen_wavelengths(surface):
    # gabor's point query takes any wavelength per call, equal to a BSDF made with them (to rounding:
    # that one prepares its second-order factors per wavelength); a BSDF
    # answering from its images takes its own wavelengths only and says which one it cannot answer.
    bsdf = glintscope.bsdf(surface, "gabor", res=24, sigma_c=5, lambda_=(0.45, 0.6))
    assert bsdf.any_wavelength
    made = glintscope.bsdf(surface, "gabor", res=24, sigma_c=5, lambda_=(0.5, 0.7))
    wi, wo = hemisphere_directions(1, 6)[0], hemisphere_directions(20, 7)
    chosen = bsdf.eval(wi, wo, wavelengths=[0.5, 0.7])
    assert chosen.shape == (20, 2) and np.allclose(chosen, made.eval(wi, wo), rtol=1e-9, atol=0)
    # One wavelength or two: the same sum.
    assert np.allclose(bsdf.eval(wi, wo, wavelengths=[0.6])[:, 0], bsdf.eval(wi, wo)[:, 1], rtol=1e-9, atol=0)
    tables = glintscope.bsdf(surface, "fft", res=24, sigma_c=5, lambda_=(0.45, 0.6))
    assert not tables.any_wavelength
    with pytest.raises(glintscope.Error, match="not 0.5 um"):
        tables.eval(wi, wo, wavelengths=[0.5])


def test_a_footprint_near_the_kernels_width_warns_that_the_albedo_is_low(surface):
    # Gabor's kernels (sigma_k = 0.5 um at one per texel) blur the window: a footprint of sigma_c = 1 um
    # keeps f = 1/(1 + 0.25) = 0.8 of its energy, so the albedo is f of the FFT's (docs/gabor.md "Flat
    # mirror"); bsdf() says so as a RuntimeWarning, and not at sigma_c = 5 um (f = 0.99).
    keys = dict(res=32, lambda_=0.5, model="rohs")
    with pytest.warns(RuntimeWarning, match="keeps f = 0.8 of the window's energy") as record:
        narrow = glintscope.bsdf(surface, "gabor", sigma_c=1, kernels_per_texel=1, **keys)
    assert narrow.warnings == [str(w.message) for w in record if w.category is RuntimeWarning]
    wi = np.array([0.0, 0.0, 1.0])
    fft = glintscope.bsdf(surface, "fft", sigma_c=1, **keys).albedo(wi)[0]
    assert narrow.albedo(wi)[0] / fft == pytest.approx(0.8, rel=0.01)
    assert glintscope.bsdf(surface, "gabor", sigma_c=5, kernels_per_texel=1, **keys).warnings == []
