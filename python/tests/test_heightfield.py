"""Heightfields between NumPy and the library: exact round trips, layouts, refusals, preparation."""
import numpy as np
import pytest

import glintscope
from conftest import run_python


def test_array_to_field_to_array_is_exact():
    heights = np.random.default_rng(3).normal(size=(37, 53)).astype(np.float32)
    field = glintscope.Heightfield(heights, texel="0.5um")
    assert field.shape == (37, 53) and field.texel_um == 0.5
    assert np.array_equal(field.heights, heights)
    assert np.array_equal(np.asarray(field), heights)
    assert not field.heights.flags.writeable  # a view of the field's own storage


def test_fortran_float32_and_strided_arrays_give_the_c_float64_field(surface):
    c64 = np.ascontiguousarray(surface.heights, dtype=np.float64)
    reference = glintscope.Heightfield(c64).heights
    for variant in (np.asfortranarray(c64), c64.astype(np.float32), np.asfortranarray(c64.astype(np.float32)),
                    np.ascontiguousarray(c64.T).T, np.pad(c64, 1)[1:-1, 1:-1]):
        assert np.array_equal(glintscope.Heightfield(variant).heights, reference)


def test_fortran_and_float32_arrays_give_the_same_lobe_bits(surface):
    c64 = np.ascontiguousarray(surface.heights, dtype=np.float64)
    keys = dict(res=32, sigma_c=5, supersample=1)
    reference = glintscope.lobe(glintscope.Heightfield(c64, periodic=True), **keys).values
    for variant in (np.asfortranarray(c64), c64.astype(np.float32)):
        assert np.array_equal(glintscope.lobe(glintscope.Heightfield(variant, periodic=True), **keys).values, reference)


@pytest.mark.parametrize("array, message", [
    (np.zeros(5), "2-D"),
    (np.zeros((2, 2, 2)), "2-D"),
    (np.zeros((0, 4)), "at least one row"),
    (np.zeros((4, 4), dtype=np.int32), "float32 or float64"),
    (np.array([[0.0, np.inf], [0.0, 0.0]]), "infinit"),
    (np.array([[0.0, np.nan], [0.0, 0.0]]), "NaN"),
])
def test_bad_arrays_are_refused_in_one_line(array, message):
    with pytest.raises(glintscope.Error, match=message) as error:
        glintscope.Heightfield(array)
    assert "\n" not in str(error.value)


def test_missing_points_are_allowed_on_request_and_filled():
    # A plane z = 0.1 x - 0.05 y with a hole: the biharmonic fill carries planes exactly.
    y, x = np.mgrid[0:32, 0:32].astype(float)
    plane = 0.1 * x - 0.05 * y
    holed = plane.copy()
    holed[10:14, 12:17] = np.nan
    field = glintscope.Heightfield(holed, allow_missing=True)
    assert field.missing == 20
    filled = field.fill()
    assert filled.missing == 0 and field.missing == 20  # a new field; the old one is unchanged
    assert np.allclose(filled.heights, plane, atol=1e-4)
    assert "prepare.1" in filled.provenance


def test_preparation_steps_match_their_definitions():
    heights = np.random.default_rng(5).normal(size=(24, 40)).astype(np.float32)
    field = glintscope.Heightfield(heights, texel=2)
    # orient: one quarter turn counter-clockwise is numpy's rot90 (row 0 at the top).
    assert np.array_equal(field.orient(rotate=90).heights, np.rot90(heights))
    assert np.array_equal(field.orient(flip_x=True).heights, heights[:, ::-1])
    # crop: (x0, y0) from the lower-left corner, so y0 = 4 um at 2 um texels drops the bottom 2 rows.
    cropped = field.crop(6, 4, 20, 10)
    assert np.array_equal(cropped.heights, heights[24 - 2 - 5:24 - 2, 3:13])
    # remove_form: a tilted copy levels back to the same residual as the original.
    y, x = np.mgrid[0:24, 0:40]
    tilted = glintscope.Heightfield(heights + 0.3 * x - 0.2 * y, texel=2)
    assert np.allclose(tilted.remove_form("plane").heights, field.remove_form(1).heights, atol=1e-4)
    # resample to half the texel keeps the mean height (bicubic interpolation of a periodic-free field).
    assert field.resample("1um").shape == (48, 80)


def test_statistics_and_iso_parameters_agree_with_numpy(surface):
    h = surface.heights.astype(float)
    stats = surface.statistics()
    assert stats["sq_um"] == pytest.approx(np.sqrt(np.mean((h - h.mean()) ** 2)), rel=1e-9)
    iso = surface.iso_parameters()
    z = h - h.mean()
    assert iso["Sq_um"] == pytest.approx(np.sqrt(np.mean(z ** 2)), rel=1e-9)
    assert iso["Ssk"] == pytest.approx(np.mean(z ** 3) / np.mean(z ** 2) ** 1.5, rel=1e-6, abs=1e-9)
    assert iso["Sz_um"] == pytest.approx(z.max() - z.min(), rel=1e-6)


def test_save_and_load_round_trip_exactly(tmp_path, surface):
    for name in ("field.npy", "field.exr", "field.x3p"):
        path = str(tmp_path / name)
        surface.save(path)
        loaded = glintscope.load(path, periodic=True, texel=surface.texel_um)
        assert np.array_equal(loaded.heights, surface.heights), name
        assert loaded.periodic


def test_generate_takes_recipe_keys_and_refuses_unknown_ones():
    field = glintscope.generate("grating", size=64, period=4, amplitude=0.1, texel="0.25um")
    assert field.shape == (64, 64) and field.texel_um == 0.25
    # Samples sit at texel centres, (c + 1/2) 0.25 um: 16 per period, the crest falls between two.
    assert float(np.max(field.heights)) == pytest.approx(0.1 * np.cos(np.pi / 16), rel=1e-6)
    with pytest.raises(glintscope.Error, match="no_such_key"):
        glintscope.generate("grating", no_such_key=1)


def test_bad_inputs_do_not_crash_the_interpreter(tmp_path):
    # Every bad input in a fresh interpreter: each must raise (glintscope.Error, or TypeError for a
    # wrong argument type), and the interpreter must finish normally.
    bad = tmp_path / "bad.npy"
    bad.write_bytes(b"\x93NUMPY garbage")
    code = f"""
import numpy as np, glintscope as g
f = g.generate('gaussian', size=64)
b = g.bsdf(f, 'fft', res=16)
cases = [
    lambda: g.Heightfield(np.zeros((3, 3, 3))),
    lambda: g.Heightfield(np.full((4, 4), np.nan)),
    lambda: g.Heightfield(np.zeros((4, 4)), texel=-1),
    lambda: g.Heightfield('not an array'),
    lambda: g.load({str(bad)!r}),
    lambda: g.load('/no/such/file.npy'),
    lambda: g.lobe(f, res=-3),
    lambda: g.lobe(f, res=10**9),
    lambda: g.lobe(f, sigma_c=float('nan')),
    lambda: g.lobe(f, incident=(95, 0)),
    lambda: g.lobe(f, method='nope'),
    lambda: g.lobe(np.zeros((4, 4))),
    lambda: g.lobe(f, lambda_=[]),
    lambda: g.ndf(f, 'fft'),
    lambda: b.eval(np.zeros((2, 2)), [0, 0, 1]),
    lambda: b.eval([np.nan, 0, 1], [0, 0, 1]),
    lambda: b.eval(np.zeros((3, 3)) + [0, 0, 1], np.zeros((4, 3)) + [0, 0, 1]),
    lambda: b.sample([0, 0, 1], [[0.5]]),
    lambda: g.generate('nope'),
    lambda: f.crop(0, 0, 1e9, 1),
    lambda: f.orient(rotate=45),
    lambda: f.remove_form(99),
]
raised = 0
for case in cases:
    try:
        case()
    except (g.Error, TypeError):
        raised += 1
print(raised, len(cases))
"""
    result = run_python(code)
    assert result.returncode == 0, result.stderr
    raised, total = map(int, result.stdout.split())
    assert raised == total, result.stdout


def test_load_takes_a_rectangular_texel_pair(tmp_path, surface):
    path = str(tmp_path / "field.npy")  # NPY states no spacing: the declared one is used as is
    surface.save(path)
    square = glintscope.load(path, texel=1)
    rectangular = glintscope.load(path, texel=(1, "2um"))
    assert (rectangular.texel_um, rectangular.texel_y_um) == (1.0, 2.0)
    assert np.array_equal(rectangular.heights, surface.heights)
    # Stretching y by 2 halves the slopes along y and doubles the correlation length along y; x keeps its own.
    one, two = square.statistics(), rectangular.statistics()
    assert two["rms_slope_x"] == one["rms_slope_x"]
    assert two["rms_slope_y"] == pytest.approx(one["rms_slope_y"] / 2, rel=1e-12)
    assert two["correlation_length_x_um"] == one["correlation_length_x_um"]
    assert two["correlation_length_y_um"] == pytest.approx(2 * one["correlation_length_y_um"], rel=1e-12)
    # The same field written at 1 x 2 um (the EXR states both spacings) reads back with the same numbers.
    written = str(tmp_path / "field.exr")
    rectangular.save(written)
    from_file = glintscope.load(written)
    assert (from_file.texel_um, from_file.texel_y_um) == (1.0, 2.0)
    exactly = dict(rel=0, abs=0, nan_ok=True)  # NaN: the autocorrelation at half the field, not reported once it decayed
    assert from_file.statistics() == pytest.approx(two, **exactly)
    assert from_file.iso_parameters() == pytest.approx(rectangular.iso_parameters(), **exactly)
    with pytest.raises(glintscope.Error, match="pair"):
        glintscope.load(path, texel=(1, 2, 3))
