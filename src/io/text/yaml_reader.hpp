// Internal: reading YAML files with errors that name file, line and the dotted key path.
#pragma once

#include <algorithm>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal::detail::yaml {

// Context for messages: the file and the dotted path of the key being read.
struct Ctx {
  const std::string& file;
  std::string path;

  Ctx child(const std::string& key) const { return {file, path.empty() ? key : path + "." + key}; }
  [[noreturn]] void fail(const YAML::Node& n, const std::string& what) const {
    const int line = n.IsDefined() ? n.Mark().line + 1 : 0;
    throw InputError({file, line, path}, what);
  }
};

inline std::string describe(const YAML::Node& n) {
  if (!n.IsDefined() || n.IsNull()) return "nothing";
  if (n.IsScalar()) return "'" + printable(n.Scalar()) + "'";
  if (n.IsSequence()) return "a list";
  return "a map";
}

// The entries of a map in file order, each key once.
class Entries {
 public:
  std::size_t count(const std::string& key) const {
    for (const auto& kv : items_)
      if (kv.first == key) return 1;
    return 0;
  }
  YAML::Node operator[](const std::string& key) const {
    for (const auto& kv : items_)
      if (kv.first == key) return kv.second;
    return YAML::Node(YAML::NodeType::Undefined);
  }
  auto begin() const { return items_.begin(); }
  auto end() const { return items_.end(); }
  void add(std::string key, YAML::Node value) { items_.emplace_back(std::move(key), std::move(value)); }

 private:
  std::vector<std::pair<std::string, YAML::Node>> items_;
};

// Checks that a map has only known keys (any key if known is empty), each once. With
// null_is_empty, a section with nothing after its key reads as an empty map.
inline Entries entries(const YAML::Node& n, const Ctx& ctx, std::initializer_list<std::string_view> known,
                       bool null_is_empty = true) {
  Entries out;
  if (null_is_empty && n.IsDefined() && n.IsNull()) return out;
  if (!n.IsMap()) ctx.fail(n, "expected a map, found " + describe(n));
  for (auto it = n.begin(); it != n.end(); ++it) {
    if (!it->first.IsScalar()) ctx.fail(it->first, "expected a plain key, found " + describe(it->first));
    const std::string key = it->first.Scalar();
    const Ctx kc = ctx.child(key);
    if (known.size() != 0 && std::find(known.begin(), known.end(), std::string_view(key)) == known.end()) {
      std::string list;
      for (auto k : known) list += (list.empty() ? "" : ", ") + std::string(k);
      kc.fail(it->first, "unknown key '" + printable(key) + "' (expected one of: " + list + ")");
    }
    if (out.count(key)) kc.fail(it->first, "duplicated key '" + printable(key) + "'");
    out.add(key, it->second);
  }
  return out;
}

inline double number(const YAML::Node& n, const Ctx& ctx) {
  if (!n.IsScalar()) ctx.fail(n, "expected a number, found " + describe(n));
  const auto v = parse_number(n.Scalar());
  if (!v) ctx.fail(n, "expected a finite number, found '" + printable(n.Scalar()) + "'");
  return *v;
}

inline std::string text(const YAML::Node& n, const Ctx& ctx) {
  if (!n.IsScalar()) ctx.fail(n, "expected text, found " + describe(n));
  return n.Scalar();
}

inline std::vector<double> numbers(const YAML::Node& n, const Ctx& ctx) {
  if (!n.IsSequence()) ctx.fail(n, "expected a list of numbers, found " + describe(n));
  std::vector<double> v;
  for (std::size_t i = 0; i < n.size(); ++i) v.push_back(number(n[i], ctx.child(std::to_string(i))));
  return v;
}

}  // namespace mtcal::detail::yaml
