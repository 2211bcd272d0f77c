"""The module's own parameters each change a result: periodic fields, load options, output
options, thread counts, validation axes, batch runs, display settings."""
import numpy as np
import pytest

import glintscope


def test_periodic_lets_a_footprint_cross_the_border(surface):
    heights = surface.heights
    edge = dict(res=16, sigma_c=5, centre=(2, 64), supersample=1)
    with pytest.raises(glintscope.Error, match="crosses the edge of the non-periodic heightfield"):
        glintscope.lobe(glintscope.Heightfield(heights, periodic=False), **edge)
    wrapped = glintscope.lobe(glintscope.Heightfield(heights, periodic=True), **edge)
    # The same footprint moved across the seam by a whole tile is the same lobe.
    moved = glintscope.lobe(glintscope.Heightfield(heights, periodic=True), **dict(edge, centre=(130, 64)))
    assert np.allclose(wrapped.values, moved.values, rtol=1e-4, atol=1e-6 * wrapped.values.max())


def test_load_options_scale_and_convert_heights(tmp_path, surface):
    path = str(tmp_path / "f.npy")
    surface.save(path)
    plain = glintscope.load(path).heights
    assert np.array_equal(glintscope.load(path, height_scale=2).heights, 2 * plain)
    assert np.allclose(glintscope.load(path, height_unit="nm").heights, plain / 1000, rtol=1e-6)
    assert glintscope.load(path, texel="250nm").texel_um == 0.25
    assert glintscope.load(path).units_assumed


def test_saved_spectral_channels_read_back_exactly(tmp_path, surface):
    lobe = glintscope.lobe(surface, res=16, sigma_c=5, lambda_=(0.45, 0.65), supersample=2)
    lobe.save(str(tmp_path / "with.exr"), spectral_channels=True)
    assert np.array_equal(glintscope.load_lobe(str(tmp_path / "with.exr")).values, lobe.values)
    lobe.save(str(tmp_path / "rgb.exr"))
    with pytest.raises(glintscope.Error, match="R, G, B"):
        glintscope.load_lobe(str(tmp_path / "rgb.exr"))
    # A wider gamut holds the same colour in other numbers.
    assert not np.array_equal(glintscope.to_rgb(lobe), glintscope.to_rgb(lobe, colour_space="lin_rec2020"))


def test_results_do_not_depend_on_the_thread_count(surface):
    bsdf = glintscope.bsdf(surface, "fft", res=16, sigma_c=5)
    wo = np.array([[0.1, 0.2, 0.97], [-0.3, 0.1, 0.95]])
    answers = []
    for threads in (1, 2):
        with glintscope.using_threads(threads):
            assert glintscope.threads() == threads
            answers.append((glintscope.lobe(surface, res=16, sigma_c=5, supersample=2).values,
                            bsdf.eval([0, 0, 1], glintscope_unit(wo))))
    assert np.array_equal(answers[0][0], answers[1][0]) and np.array_equal(answers[0][1], answers[1][1])


def glintscope_unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def test_validation_axes_make_their_rows(surface):
    rows = glintscope.validate(surface, res=16, sigma_c=5, supersample=2, models=["rohs", "kirchhoff"],
                               kernels_per_texel=[1, 2])
    assert [(r["model"], r["kernels_per_texel"]) for r in rows] == [
        ("rohs", 1), ("rohs", 2), ("kirchhoff", 1), ("kirchhoff", 2)]
    # More kernels per texel approximate the FFT better (Yan 2018 §5).
    assert rows[1]["relative_l2"] < rows[0]["relative_l2"]


def test_batch_computes_once_then_reuses_its_panels(tmp_path):
    manifest = tmp_path / "fig.toml"
    manifest.write_text('title = "t"\noutput = "fig.png"\n[defaults]\nres = 16\nsigma_c = "5um"\nsupersample = 2\n'
                        '[[row]]\nlabel = "g"\nheightfield = "builtin:grating"\n'
                        '[[column]]\nlabel = "fft"\nmethod = "fft"\n[[column]]\nlabel = "geometric"\nmethod = "geometric"\n')
    first = glintscope.batch(str(manifest))
    assert first["computed"] == 2 and (tmp_path / "fig.png").exists()
    again = glintscope.batch(str(manifest))
    assert again["computed"] == 0 and again["up_to_date"] == 2
    assert glintscope.batch(str(manifest), force=True)["computed"] == 2


def test_display_exposure_and_log_scale(surface):
    lobe = glintscope.lobe(surface, res=16, sigma_c=5, supersample=2)
    dark, ev = glintscope.to_display(lobe, exposure=-4.0)
    bright, _ = glintscope.to_display(lobe, exposure=0.0)
    assert ev == -4.0 and dark.sum() < bright.sum()
    linear, _ = glintscope.to_display(lobe)
    logged, log_ev = glintscope.to_display(lobe, log=True)
    # Auto on a log scale puts the maximum at white (linear: the 99.5th percentile) and lifts the
    # pixels a decade or two below it into the upper half of the range.
    assert log_ev == pytest.approx(-np.log2(float(lobe.values.max())), rel=1e-3)
    assert (logged > 128).sum() > (linear > 128).sum()
