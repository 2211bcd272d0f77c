"""Times the Python module's calls that bench/python_call_bench.cpp times from C++
(docs/performance.md "Python module"): a small lobe (its per-call cost) and BSDF eval per pair.

Usage: PYTHONPATH=build/python /usr/bin/python3 scripts/python-bench.py
"""
import statistics
import time
import warnings

import numpy as np

import glintscope

warnings.simplefilter("ignore", RuntimeWarning)


def median_seconds(call, repeats, clock=time.perf_counter):
    times = []
    for _ in range(repeats):
        start = clock()
        call()
        times.append(clock() - start)
    return statistics.median(times)


small = glintscope.generate("gaussian", size=64, sigma_h=0.05, correlation_length_x=4, correlation_length_y=4)
glintscope.lobe(small, "fft", sigma_c=2, res=16, supersample=1)  # the interpolant, kept on the object
def call():
    glintscope.lobe(small, "fft", sigma_c=2, res=16, supersample=1)


wall, cpu = median_seconds(call, 300), median_seconds(call, 300, time.process_time)
print(f"small lobe from Python: {wall * 1e6:.0f} us wall, {cpu * 1e6:.0f} us CPU per call (medians of 300)")

field = glintscope.generate("isotropic")
bsdf = glintscope.bsdf(field, "gabor", sigma_c=10, res=256, kernels_per_texel=1)
wi = np.array([np.sin(np.radians(20)), 0.0, np.cos(np.radians(20))])
rng = np.random.default_rng(1)
x, y = rng.uniform(-1, 1, size=(2, 1_400_000))
inside = x ** 2 + y ** 2 < 1
x, y = x[inside][:1_000_000], y[inside][:1_000_000]
wo = np.stack([x, y, np.sqrt(1 - x ** 2 - y ** 2)], axis=-1)
bsdf.eval(wi, wo[:10])  # the table of wi
for threads in (1, 2):
    with glintscope.using_threads(threads):
        seconds = median_seconds(lambda: bsdf.eval(wi, wo), 3)
    print(f"bsdf.eval gabor 1 kernel/texel, 10^6 pairs, {threads} thread(s): {seconds * 1e6 / len(wo):.3f} us per pair")
