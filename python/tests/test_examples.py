"""The examples under scripts/examples/ run, write their figures, and print numbers that hold."""
import os
import re
import subprocess
import sys

from conftest import SOURCE_DIR


def run_example(name, tmp_path):
    script = os.path.join(SOURCE_DIR, "scripts", "examples", name)
    result = subprocess.run([sys.executable, "-W", "ignore::RuntimeWarning", script, str(tmp_path)],
                            capture_output=True, text=True, timeout=180)
    assert result.returncode == 0, result.stderr
    figure = tmp_path / name.replace(".py", ".png")
    assert figure.stat().st_size > 20_000  # a rendered figure, not an empty canvas
    return result.stdout


def numbers(pattern, text):
    return [float(x) for x in re.findall(pattern, text)]


def test_gabor_vs_fft(tmp_path):
    out = run_example("gabor_vs_fft.py", tmp_path)
    assert numbers(r"relative L2 ([\d.]+)", out)[0] < 0.1  # Gabor approximates the FFT ground truth
    assert abs(numbers(r"energy ratio ([\d.]+)", out)[0] - 1) < 0.05


def test_sigma_sweep(tmp_path):
    out = run_example("sigma_sweep.py", tmp_path)
    albedos = numbers(r"albedo ([\d.]+)", out)
    assert len(albedos) == 5 and all(abs(a - 1) < 0.01 for a in albedos)  # energy is conserved


def test_scan_pndf(tmp_path):
    out = run_example("scan_pndf.py", tmp_path)
    beckmann, ggx = numbers(r"relative error ([\d.]+)", out)
    assert beckmann < ggx  # a Gaussian surface's slopes are Gaussian: Beckmann fits it better
    assert (tmp_path / "stand_in_scan.x3p").exists()
