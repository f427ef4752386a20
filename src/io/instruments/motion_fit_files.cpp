#include "mtcal/io/instruments/motion_fit_files.hpp"

#include "mtcal/io/instruments/iso230_files.hpp"
#include "mtcal/io/instruments/laser_files.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

std::pair<std::string, std::string> split_motion_file_spec(const std::string& spec) {
  const auto eq = spec.find('=');
  if (eq != std::string::npos && eq >= 3 && eq <= 4 && spec[0] == 'E') return {spec.substr(0, eq), spec.substr(eq + 1)};
  return {"", spec};
}

MotionFileFits fit_motion_files(const std::vector<std::string>& specs, const MotionFileOptions& o) {
  MotionFileFits out;
  for (const auto& spec : specs) {
    auto [name, path] = split_motion_file_spec(spec);
    PositioningRuns runs;
    if (o.format == "laser" || (o.format == "auto" && looks_like_laser(path))) {
      const LaserFile lf = read_laser_file(path);
      runs = lf.runs;
      if (name.empty()) name = laser_error_name(lf);
    } else {
      runs = read_positioning_file(path, o.format, o.unit, o.target_unit);
    }
    if (name.empty())
      throw InputError({path, 0, ""},
                       "the file does not say which error it measured: name it, e.g. EXX=" + path + " or EYX=" + path);
    if (o.wrap > 0) runs = merge_wrapped_targets(runs, o.wrap);
    out.warnings.insert(out.warnings.end(), runs.warnings.begin(), runs.warnings.end());
    MotionFit fit;
    out.errors.push_back(estimate_motion_error(runs, name, o.fit, &fit));
    out.fits.push_back(fit);
  }
  check_distinct(out.errors);
  return out;
}

}  // namespace mtcal
