// A zip archive in memory (libzip): the "write compensation" download of mtcal serve.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace mtcal::server {

// A zip archive (deflated entries, UTF-8 names) of the files (name, content) in this order.
// Throws Error with libzip's message when it cannot be made.
std::string zip_archive(const std::vector<std::pair<std::string, std::string>>& files);

}  // namespace mtcal::server
