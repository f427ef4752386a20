// libFuzzer target: the history store's JSON-lines reader (io/history/store.hpp, import_jsonl)
// into an in-memory SQLite store; a refused line must be an InputError and leave nothing behind.
#include <sstream>

#include "fuzz_common.hpp"
#include "mtcal/io/history/store.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto store = mtcal::open_history_store("sqlite::memory:");
  std::istringstream in{std::string(mtcal::fuzz::as_text(data, size))};
  const std::size_t before = store->list().size();
  try {
    (void)mtcal::import_jsonl(*store, in, "fuzz.jsonl");
  } catch (const mtcal::InputError&) {
    if (store->list().size() != before) __builtin_trap();  // a refused import stored something
  } catch (const mtcal::Error&) {
  }
  return 0;
}
