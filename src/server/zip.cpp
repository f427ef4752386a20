// A zip archive in memory with libzip (Debian's libzip-dev): an in-memory source that the archive
// is written to, read back after zip_close (libzip's documented pattern for archives in memory,
// zip_source_buffer_create(3) and zip_open_from_source(3)).
#include "zip.hpp"

#include <zip.h>

#include <memory>

#include "mtcal/util/errors.hpp"

namespace mtcal::server {

namespace {

[[noreturn]] void fail(const std::string& what, zip_error_t* e) {
  const std::string message = std::string("cannot make the zip archive: ") + what + ": " + zip_error_strerror(e);
  zip_error_fini(e);
  throw Error(message);
}

}  // namespace

std::string zip_archive(const std::vector<std::pair<std::string, std::string>>& files) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* memory = zip_source_buffer_create(nullptr, 0, 0, &error);
  if (!memory) fail("memory", &error);
  std::unique_ptr<zip_source_t, decltype(&zip_source_free)> keep(memory, &zip_source_free);
  zip_source_keep(memory);  // zip_close/zip_discard release it once; this reference keeps it for reading
  zip_t* archive = zip_open_from_source(memory, ZIP_TRUNCATE, &error);
  if (!archive) fail("open", &error);
  for (const auto& [name, content] : files) {
    // The content is copied by zip_close below, while these strings are alive.
    zip_source_t* s = zip_source_buffer(archive, content.data(), content.size(), 0);
    if (!s || zip_file_add(archive, name.c_str(), s, ZIP_FL_ENC_UTF_8) < 0) {
      if (s) zip_source_free(s);
      zip_error_set(&error, zip_error_code_zip(zip_get_error(archive)), zip_error_code_system(zip_get_error(archive)));
      zip_discard(archive);
      fail(name, &error);
    }
  }
  if (zip_close(archive) < 0) {
    zip_error_set(&error, zip_error_code_zip(zip_get_error(archive)), zip_error_code_system(zip_get_error(archive)));
    zip_discard(archive);
    fail("close", &error);
  }
  zip_stat_t st;
  if (zip_source_stat(memory, &st) < 0 || zip_source_open(memory) < 0) {
    zip_error_set(&error, zip_error_code_zip(zip_source_error(memory)), 0);
    fail("read back", &error);
  }
  std::string out(static_cast<std::size_t>(st.size), '\0');
  const zip_int64_t n = zip_source_read(memory, out.data(), st.size);
  zip_source_close(memory);
  if (n < 0 || static_cast<zip_uint64_t>(n) != st.size) {
    zip_error_set(&error, ZIP_ER_READ, 0);
    fail("read back", &error);
  }
  zip_error_fini(&error);
  return out;
}

}  // namespace mtcal::server
