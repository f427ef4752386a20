// For the grid-aware numpy peer (bench/grid_peer.py): each axis' actual and nominal transform at
// each of its grid values, from the independent chain of naive_chain.hpp (not the library's
// kernel), so that the peer combines the same factors by broadcasting.
//
//   mtcal_grid_factors MACHINE.yaml "C=0:350:36,B=...,..." OUT_PREFIX
//
// writes OUT_PREFIX.K.actual.f64 and OUT_PREFIX.K.nominal.f64 (little-endian doubles, values x 4 x 4
// row-major, K the axis in chain order; the constant factors before the first axis are folded
// into axis 0's, those after the last axis into the last one's) and prints the counts per axis.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "naive_chain.hpp"

using namespace mtcal;

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: mtcal_grid_factors MACHINE.yaml GRID OUT_PREFIX\n";
    return 2;
  }
  const Machine m = load_machine(argv[1]);
  const auto grid = parse_grid(m, argv[2], "grid");
  const std::size_t n = m.axes.size();
  // naive_chain's factor counts: actual 2 before the axes, 8 per axis, 3 after; nominal 1, 5, 2.
  for (int errors = 1; errors >= 0; --errors) {
    const std::size_t pre = errors ? 2 : 1, per = errors ? 8 : 5;
    for (std::size_t k = 0; k < n; ++k) {
      std::ofstream out(std::string(argv[3]) + "." + std::to_string(k) + (errors ? ".actual.f64" : ".nominal.f64"),
                        std::ios::binary);
      for (double v : grid[k]) {
        std::vector<double> q(n, 0.0);
        q[k] = v;
        const auto f = bench::naive_chain(m, q, {}, errors != 0);
        const std::size_t begin = k == 0 ? 0 : pre + per * k, end = k + 1 == n ? f.size() : pre + per * (k + 1);
        Eigen::Matrix4d p = Eigen::Matrix4d::Identity();
        for (std::size_t i = begin; i < end; ++i) p = p * f[i];
        const Eigen::Matrix<double, 4, 4, Eigen::RowMajor> r = p;
        out.write(reinterpret_cast<const char*>(r.data()), sizeof(double) * 16);
      }
    }
  }
  for (std::size_t k = 0; k < n; ++k) std::cout << grid[k].size() << (k + 1 < n ? " " : "\n");
  return 0;
}
