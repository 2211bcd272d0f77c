"""Lobes through the library pipeline: the same bits and metadata as the CLI's EXR, the CLI's error
messages, and comparison, fits and colour on the results."""
import subprocess

import numpy as np
import pytest

import glintscope

KEYS = dict(res=32, sigma_c="5um", incident=(20, 30), lambda_="0.5um,0.6um")
CLI_FLAGS = ["--res", "32", "--sigma-c", "5um", "--incident", "20,30", "--lambda", "0.5um,0.6um"]


@pytest.fixture(scope="module")
def surface_file(tmp_path_factory, surface):
    path = str(tmp_path_factory.mktemp("field") / "surface.npy")
    surface.save(path)
    return path


def cli_lobe(cli, tmp_path, heightfield, *flags, command="lobe"):
    out = str(tmp_path / "cli.exr")
    result = subprocess.run([cli, command, heightfield, *flags, "--spectral-channels", "-o", out], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    return glintscope.load_lobe(out)


@pytest.mark.parametrize("method, command", [("fft", "lobe"), ("gabor", "lobe"), ("pndf", "ndf")])
def test_the_module_lobe_is_the_cli_exr_bit_for_bit(cli, tmp_path, surface_file, method, command):
    function = glintscope.lobe if command == "lobe" else glintscope.ndf
    mine = function(surface_file, method, periodic=True, **KEYS)
    theirs = cli_lobe(cli, tmp_path, surface_file, "--periodic", "yes", "--method", method, *CLI_FLAGS, command=command)
    assert mine.values.shape == (2, 32, 32) and mine.values.dtype == np.float32
    assert np.array_equal(mine.values, theirs.values)
    # Every entry but the CLI's invocation, which only the CLI has, and the time the run took.
    expected = {k: v for k, v in theirs.metadata.items() if k not in ("command_line", "run.seconds")}
    assert {k: v for k, v in mine.metadata.items() if k != "run.seconds"} == expected


def test_a_heightfield_object_gives_the_bits_of_its_file(surface_file):
    from_file = glintscope.lobe(surface_file, periodic=True, **KEYS)
    from_object = glintscope.lobe(glintscope.load(surface_file, periodic=True), **KEYS)
    assert np.array_equal(from_object.values, from_file.values)
    # The query and the method's choices agree; only the file's own record differs.
    differ = {k for k in from_file.metadata if from_file.metadata[k] != from_object.metadata.get(k)}
    assert differ <= {"query.heightfield", "query.periodic", "heightfield.md5", "run.seconds"}, differ


def test_units_as_strings_or_numbers_in_micrometres(surface):
    a = glintscope.lobe(surface, res=24, sigma_c="5um", lambda_="500nm", supersample=2)
    b = glintscope.lobe(surface, res=24, sigma_c=5, lambda_=0.5, supersample=2)
    assert np.array_equal(a.values, b.values)
    values, metadata = a
    assert metadata["query.sigma_c"] == "5" and values.shape == (1, 24, 24)
    # NumPy scalars and arrays are values too; booleans are yes/no.
    c = glintscope.lobe(surface, res=np.int64(24), sigma_c=np.float32(5), lambda_=np.array([0.5]), supersample=2)
    assert np.array_equal(c.values, a.values)


def test_booleans_read_as_yes_and_no(tmp_path, surface):
    path = str(tmp_path / "f.npy")
    surface.save(path)
    edge = dict(res=16, sigma_c=5, centre=(2, 64), supersample=1)
    assert glintscope.lobe(path, periodic=np.bool_(True), **edge).metadata["query.periodic"] == "yes"
    with pytest.raises(glintscope.Error, match="non-periodic"):
        glintscope.lobe(path, periodic=False, **edge)


def test_method_options_are_keywords(surface):
    one = glintscope.lobe(surface, "gabor", res=24, sigma_c=5, kernels_per_texel=1, supersample=2)
    two = glintscope.lobe(surface, "gabor", res=24, sigma_c=5, kernels_per_texel=2, supersample=2)
    assert one.metadata["query.option.kernels_per_texel"] == "1"
    assert not np.array_equal(one.values, two.values)


@pytest.mark.parametrize("keys, flags", [
    (dict(sigma_c="10parsec"), ["--sigma-c", "10parsec"]),
    (dict(model="nope"), ["--model", "nope"]),
    (dict(res=0), ["--res", "0"]),
    (dict(incident=(95, 0)), ["--incident", "95,0"]),
    (dict(material="Unobtainium"), ["--material", "Unobtainium"]),
    (dict(footprints="grid:0"), ["--footprints", "grid:0"]),
])
def test_bad_values_raise_the_cli_message(cli, tmp_path, surface_file, keys, flags):
    result = subprocess.run([cli, "lobe", surface_file, *flags, "-o", str(tmp_path / "x.exr")],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 1
    cli_message = result.stderr.strip().removeprefix("glintscope: error: ")
    with pytest.raises(glintscope.Error) as error:
        glintscope.lobe(surface_file, **keys)
    assert str(error.value) == cli_message


def test_unknown_keys_and_methods_are_named(surface):
    with pytest.raises(glintscope.Error, match="unknown query key 'sigma'"):
        glintscope.lobe(surface, sigma=5)
    with pytest.raises(glintscope.Error, match="nope"):
        glintscope.lobe(surface, "nope")
    with pytest.raises(glintscope.Error, match="glintscope.load"):
        glintscope.lobe(surface, texel=2)


def test_compare_and_difference(surface):
    fft = glintscope.lobe(surface, res=32, sigma_c=5, supersample=2)
    gabor = glintscope.lobe(surface, "gabor", res=32, sigma_c=5, supersample=2)
    same = glintscope.compare(fft, fft)[0]
    assert same["relative_l2"] == 0.0 and same["energy_ratio"] == 1.0
    layer = glintscope.compare(gabor, fft)[0]
    difference = glintscope.difference(gabor, fft).values
    assert np.array_equal(difference, gabor.values - fft.values)
    assert layer["max_abs_difference"] == pytest.approx(np.abs(difference).max(), rel=1e-6)
    assert 0.0 < layer["relative_l2"] < 0.2  # Yan 2018: Gabor kernels approximate the FFT ground truth


def test_averaged_footprints_are_the_mean_of_single_ones(surface):
    mean = glintscope.ndf(surface, res=24, sigma_c=4, footprints=2)
    assert mean.metadata["footprints.count"] == "2"
    assert mean.disk_sum() == pytest.approx(1.0, abs=0.02)  # an NDF is normalised


def test_validate_reports_the_compare_numbers(surface):
    rows = glintscope.validate(surface, res=24, sigma_c=5, supersample=2)
    assert len(rows) == 1
    pair = glintscope.compare(glintscope.lobe(surface, "gabor", res=24, sigma_c=5, supersample=2),
                              glintscope.lobe(surface, "fft", res=24, sigma_c=5, supersample=2))[0]
    assert rows[0]["relative_l2"] == pytest.approx(pair["relative_l2"], rel=1e-12)


def test_fitted_ggx_recovers_a_ggx_ndf():
    # Fit a GGX to the image of a GGX model: the fit must return the model's roughness.
    surface = glintscope.generate("gaussian", size=128, sigma_h=0.3, correlation_length_x=6, correlation_length_y=6)
    pndf = glintscope.ndf(surface, res=32, footprint="whole")
    fit = glintscope.fit_ndf(pndf, "ggx")
    again = glintscope.fit_ndf(fit["image"], "ggx")
    assert again["alpha_x"] == pytest.approx(fit["alpha_x"], rel=1e-3)
    assert again["relative_error"] < 1e-3
    # A Gaussian surface of rms slope s has a Beckmann NDF of alpha = sqrt(2) s.
    beckmann = glintscope.fit_ndf(pndf, "beckmann")
    slope = surface.statistics()["rms_slope_x"]
    assert beckmann["alpha_x"] == pytest.approx(np.sqrt(2) * slope, rel=0.15)


def test_colour_of_a_grey_lobe_is_neutral_and_its_luminance_is_the_lobe(surface):
    # A wavelength-independent lobe (geometric optics) over 8 wavelengths is exactly neutral
    # (docs/colour.md), and a single-wavelength lobe is the D65 white scaled to Y = f_r.
    grey = glintscope.lobe(surface, "geometric", res=24, spectral=8)
    rgb = glintscope.to_rgb(grey)
    assert rgb.shape == (24, 24, 3)
    assert np.allclose(rgb[..., 0], rgb[..., 1], rtol=1e-4, atol=1e-6)
    assert np.allclose(rgb[..., 2], rgb[..., 1], rtol=1e-4, atol=1e-6)
    single = glintscope.lobe(surface, "geometric", res=24)
    xyz = glintscope.to_xyz(single)
    assert np.allclose(xyz[..., 1], single.values[0], rtol=1e-6)
    pixels, ev = glintscope.to_display(grey, exposure=0.0)
    assert pixels.dtype == np.uint8 and ev == 0.0
