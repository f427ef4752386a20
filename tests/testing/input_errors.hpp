// Test helpers for readers: temporary input files and the location an InputError names.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "mtcal/util/errors.hpp"

namespace mtcal::testing {

// Writes text to a file of that name in the temporary directory and returns its path.
inline std::string write_temp(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / name;
  std::ofstream(p) << text;
  return p.string();
}

// The location of the InputError that f throws (a test failure if it throws none).
template <class F>
SourceLocation error_at(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.where();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

// The message of the InputError that f throws (a test failure if it throws none).
template <class F>
std::string error_message(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

}  // namespace mtcal::testing
