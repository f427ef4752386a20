// Uses the installed mtcal: reads a machine file and evaluates one configuration.
#include <cmath>
#include <cstdio>
#include <exception>
#include <vector>

#include <mtcal/io/model/machine_file.hpp>
#include <mtcal/kinematics/error_model.hpp>
#include <mtcal/version.hpp>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer MACHINE.yaml\n");
    return 2;
  }
  try {
    const mtcal::ErrorModel model(mtcal::load_machine(argv[1]));
    const std::vector<double> q{100.0, 50.0, -200.0};  // X Y Z in mm, chain order
    const mtcal::VolumetricError e = model.evaluate(q);
    std::printf("mtcal %s: error at X100 Y50 Z-200: %.9f %.9f %.9f mm\n", mtcal::version().c_str(), e.translation.x(),
                e.translation.y(), e.translation.z());
    // What `mtcal eval -m examples/machines/vmc-3axis.yaml --at X=100,Y=50,Z=-200 --json` prints.
    const double expected[3] = {-0.0022624953436292117, -0.00135600721993967, -0.002203952115678476};
    for (int i = 0; i < 3; ++i)
      if (std::abs(e.translation[i] - expected[i]) > 1e-9) {
        std::fprintf(stderr, "component %d: %.12g, expected %.12g\n", i, e.translation[i], expected[i]);
        return 1;
      }
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "consumer: %s\n", ex.what());
    return 1;
  }
  return 0;
}
