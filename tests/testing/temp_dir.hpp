// A temporary folder for a test (mkdtemp under /tmp), removed with everything in it when the object goes.
#pragma once

#include <stdlib.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace mtcal::testing {

struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& prefix = "mtcal-test") {
    std::string templ = "/tmp/" + prefix + "-XXXXXX";
    path = ::mkdtemp(templ.data());
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

}  // namespace mtcal::testing
