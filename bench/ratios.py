#!/usr/bin/python3
"""The ratios of issue 18 from a Google Benchmark JSON file (mtcal_bench --benchmark_out=FILE).

    /usr/bin/python3 bench/ratios.py FILE

Each line: a measurement against its baseline of the same run (CPU time of the benchmark's
thread; real time for the Monte Carlo thread counts), and the
configurations per second per core of the error kernels. A benchmark missing from the file
(filtered out) prints '-'.
"""
import json
import sys

# (what, numerator benchmark, denominator benchmark): ratio = numerator time / denominator time.
RATIOS = [
    ("history rank 1000 machines x 120 (weighted): QR baseline / closed form", "BM_HistoryRank_QR_Baseline/1000",
     "BM_HistoryRank/1000/1"),
    ("regress 150 rows: refits / hat matrix", "BM_Regress_Refit_Baseline/150/iterations:1", "BM_Regress_HatMatrix/150"),
    ("regress: 1000 rows / 150 rows (hat matrix; linear in n)", "BM_Regress_HatMatrix/1000", "BM_Regress_HatMatrix/150"),
    ("HU40T grid 1e6, 1 thread: point by point / grid kernel", "BM_GridPointByPoint_Hu40t_Baseline/1048576/iterations:1",
     "BM_GridKernel_Hu40t/1048576"),
    ("HU40T grid 1e6: stream (fill, checks, extremes) / kernel", "BM_EvalGrid_Hu40t/1048576", "BM_GridKernel_Hu40t/1048576"),
    ("HU40T grid 3e6: stream / kernel", "BM_EvalGrid_Hu40t/3040000", "BM_GridKernel_Hu40t/3040000"),
    ("HU40T grid 1e6, 1 thread: stream + CSV / kernel", "BM_EvalGridCsv_Hu40t/1/real_time",
     "BM_GridKernel_Hu40t/1048576"),
    ("HU40T grid 1e6, 1 thread: stream + .npy / kernel", "BM_EvalGridNpy_Hu40t/1048576", "BM_GridKernel_Hu40t/1048576"),
    ("HU40T grid 3e6, 1 thread: stream + .npy / kernel", "BM_EvalGridNpy_Hu40t/3040000", "BM_GridKernel_Hu40t/3040000"),
    ("5-axis list: naive 4x4 chain / batch kernel (1 thread)", "BM_Naive_5axis", "BM_Batch_5axis/threads:1/real_time"),
    ("3-axis list: naive 4x4 chain / batch kernel (1 thread)", "BM_Naive_3axis", "BM_Batch_3axis/threads:1/real_time"),
    ("Monte Carlo 1000 runs: 1 thread / 2 threads (wall)", "BM_MonteCarlo_1000/1/iterations:1/real_time",
     "BM_MonteCarlo_1000/2/iterations:1/real_time"),
    ("volumetric HU40T 1e6, 1 thread: map held / streamed (same bits)", "BM_VolumetricInMemory_Hu40t_Baseline",
     "BM_VolumetricStream_Hu40t/0"),
    ("volumetric HU40T 1e6, 1 thread: map held / streamed (grid kernel)", "BM_VolumetricInMemory_Hu40t_Baseline",
     "BM_VolumetricStream_Hu40t/1"),
    ("triples 360: all triples / least-squares circle", "BM_Triples_360/threads:1/real_time", "BM_LeastSquares_360"),
    ("HU40T list (Fourier on B, C) / its forms as polynomials, 1 thread", "BM_Forms_Hu40t",
     "BM_Forms_Hu40tPolynomial_Baseline"),
    ("3-axis VMC list (a table) / its form as a polynomial, 1 thread", "BM_Forms_3axisTable",
     "BM_Forms_3axisPolynomial_Baseline"),
    ("5-axis list (polynomials), 1 thread: baseline level / AVX2", "BM_Isa_5axis/isa:0", "BM_Isa_5axis/isa:1"),
    ("5-axis list (polynomials), 1 thread: baseline level / AVX-512", "BM_Isa_5axis/isa:0", "BM_Isa_5axis/isa:2"),
    ("HU40T list (Fourier), 1 thread: baseline level / AVX2", "BM_Isa_Hu40t/isa:0", "BM_Isa_Hu40t/isa:1"),
    ("HU40T list (Fourier), 1 thread: baseline level / AVX-512", "BM_Isa_Hu40t/isa:0", "BM_Isa_Hu40t/isa:2"),
    ("3-axis list (table), 1 thread: baseline level / AVX2", "BM_Isa_3axis/isa:0", "BM_Isa_3axis/isa:1"),
    ("3-axis list (table), 1 thread: baseline level / AVX-512", "BM_Isa_3axis/isa:0", "BM_Isa_3axis/isa:2"),
    ("HU40T grid 1e6, 1 thread: baseline level / AVX2", "BM_GridKernelIsa_Hu40t/isa:0", "BM_GridKernelIsa_Hu40t/isa:1"),
    ("HU40T grid 1e6, 1 thread: baseline level / AVX-512", "BM_GridKernelIsa_Hu40t/isa:0",
     "BM_GridKernelIsa_Hu40t/isa:2"),
]
# Configurations per second on one core.
RATES = [
    ("3-axis point list, batch kernel", "BM_Batch_3axis/threads:1/real_time"),
    ("5-axis (wCBXfYZt, polynomials) point list, batch kernel", "BM_Batch_5axis/threads:1/real_time"),
    ("5-axis HU40T example (Fourier) point list, batch kernel", "BM_Forms_Hu40t"),
    ("5-axis (polynomials) point list, AVX-512 level", "BM_Isa_5axis/isa:2"),
    ("5-axis (polynomials) point list, AVX2 level", "BM_Isa_5axis/isa:1"),
    ("5-axis (polynomials) point list, baseline level", "BM_Isa_5axis/isa:0"),
    ("HU40T example (Fourier) point list, AVX-512 level", "BM_Isa_Hu40t/isa:2"),
    ("HU40T example (Fourier) point list, AVX2 level", "BM_Isa_Hu40t/isa:1"),
    ("3-axis (table) point list, AVX-512 level", "BM_Isa_3axis/isa:2"),
    ("3-axis (table) point list, AVX2 level", "BM_Isa_3axis/isa:1"),
    ("5-axis (HU40T) grid 1e6, grid kernel, AVX-512 level", "BM_GridKernelIsa_Hu40t/isa:2"),
    ("5-axis (HU40T) grid 1e6, grid kernel, AVX2 level", "BM_GridKernelIsa_Hu40t/isa:1"),
    ("5-axis (HU40T) grid 1e6, grid kernel", "BM_GridKernel_Hu40t/1048576"),
    ("5-axis (HU40T) grid 3e6, grid kernel", "BM_GridKernel_Hu40t/3040000"),
    ("5-axis (HU40T) grid 3e6, stream", "BM_EvalGrid_Hu40t/3040000"),
    ("5-axis (HU40T) volumetric 1e6, streamed VA (2 passes)", "BM_VolumetricStream_Hu40t/0"),
    ("5-axis (HU40T) volumetric 1e6, streamed VA, grid kernel", "BM_VolumetricStream_Hu40t/1"),
]


def main():
    data = json.load(open(sys.argv[1]))
    runs = {b["name"]: b for b in data["benchmarks"] if b.get("run_type", "iteration") == "iteration"}

    def seconds(name):
        b = runs.get(name)
        if not b:
            return None
        scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[b.get("time_unit", "ns")]
        # CPU time of the calling thread: on a shared machine wall time also counts other
        # people's work; real time only where the comparison is between thread counts.
        t = b["real_time"] if name.startswith("BM_MonteCarlo") else b["cpu_time"]
        return t * scale

    print(f"machine: {data['context'].get('num_cpus')} CPUs at {data['context'].get('mhz_per_cpu')} MHz, "
          f"load average {data['context'].get('load_avg')}")
    for what, num, den in RATIOS:
        a, b = seconds(num), seconds(den)
        print(f"  {what:<66} {a / b:>9.2f}x" if a and b else f"  {what:<66} {'-':>10}")
    # The limit: multiply-then-add throughput of one core per level (BM_PeakMulAdd, flop/s), and
    # the kernels' own operation count per configuration (counter flops_per_config).
    peaks = {i: runs[f"BM_PeakMulAdd/isa:{i}"]["items_per_second"] for i in range(3)
             if f"BM_PeakMulAdd/isa:{i}" in runs and runs[f"BM_PeakMulAdd/isa:{i}"].get("items_per_second")}
    if peaks:
        names = {0: "baseline", 1: "AVX2", 2: "AVX-512"}
        print("peak multiply-add of one core: " + ", ".join(f"{names[i]} {v / 1e9:.1f} Gflop/s" for i, v in peaks.items()))
    print("configurations / s / core (flops a configuration, Gflop/s, share of the level's peak):")
    for what, name in RATES:
        b = runs.get(name)
        # items_per_second is per real time for UseRealTime benchmarks: rescaled to CPU time.
        rate = b.get("items_per_second") * b["real_time"] / b["cpu_time"] if b and b.get("items_per_second") else None
        if b and "real_time" not in name:
            rate = b.get("items_per_second")
        if not rate:
            print(f"  {what:<66} {'-':>10}")
            continue
        line = f"  {what:<66} {rate / 1e6:>8.2f} M"
        flops = b.get("flops_per_config")
        level = int(name.split("/isa:")[1]) if "/isa:" in name else (max(peaks) if peaks else None)
        if flops and level in peaks:
            gflops = rate * flops / 1e9
            line += f"  {flops:>6.0f}  {gflops:>6.1f}  {100 * gflops * 1e9 / peaks[level]:>4.0f} %"
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
