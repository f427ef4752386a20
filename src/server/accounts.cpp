// Roles, Argon2id password hashes and tokens through libsodium, login throttling.
#include "mtcal/server/accounts.hpp"

#include <sodium.h>

#include <stdexcept>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal::server {

namespace {

void init_sodium() {
  static const int rc = sodium_init();  // thread-safe once; < 0: unusable
  if (rc < 0) throw Error("libsodium could not be initialised");
}

}  // namespace

std::string_view to_string(Role r) {
  switch (r) {
    case Role::Viewer: return "viewer";
    case Role::Engineer: return "engineer";
    case Role::Admin: return "admin";
  }
  return "viewer";
}

std::optional<Role> parse_role(std::string_view name) {
  if (name == "viewer") return Role::Viewer;
  if (name == "engineer") return Role::Engineer;
  if (name == "admin") return Role::Admin;
  return std::nullopt;
}

std::string hash_password(std::string_view password, KdfCost cost) {
  init_sodium();
  unsigned long long ops = crypto_pwhash_OPSLIMIT_INTERACTIVE;
  std::size_t mem = crypto_pwhash_MEMLIMIT_INTERACTIVE;
  if (cost == KdfCost::Moderate) {
    ops = crypto_pwhash_OPSLIMIT_MODERATE;
    mem = crypto_pwhash_MEMLIMIT_MODERATE;
  } else if (cost == KdfCost::Minimum) {
    ops = crypto_pwhash_OPSLIMIT_MIN;
    mem = crypto_pwhash_MEMLIMIT_MIN;
  }
  char out[crypto_pwhash_STRBYTES];
  if (crypto_pwhash_str_alg(out, password.data(), password.size(), ops, mem, crypto_pwhash_ALG_ARGON2ID13) != 0)
    throw Error(fmt::format("cannot hash the password: libsodium could not allocate {} MiB", mem >> 20));
  return out;
}

bool verify_password(std::string_view password, const std::string& hash) {
  init_sodium();
  if (hash.empty() || hash.size() >= crypto_pwhash_STRBYTES) return false;
  return crypto_pwhash_str_verify(hash.c_str(), password.data(), password.size()) == 0;
}

std::string password_problem(std::string_view password) {
  if (password.size() < 10) return fmt::format("expected a password of at least 10 characters, found {}", password.size());
  if (password.size() > 1024) return "expected a password of at most 1024 characters";
  return {};
}

std::string user_name_problem(std::string_view name) {
  if (name.empty() || name.size() > 64) return "expected a user name of 1 to 64 characters";
  for (const char c : name)
    if (c <= ' ' || c > '~' || c == '"' || c == '\'' || c == '<' || c == '>' || c == '&')
      return "expected a user name of printable ASCII without space, quotes, '<', '>' or '&'";
  return {};
}

std::string random_token() {
  init_sodium();
  unsigned char bytes[32];
  randombytes_buf(bytes, sizeof bytes);
  char hex[sizeof bytes * 2 + 1];
  sodium_bin2hex(hex, sizeof hex, bytes, sizeof bytes);
  return hex;
}

bool tokens_equal(std::string_view a, std::string_view b) {
  init_sodium();
  return a.size() == b.size() && !a.empty() && sodium_memcmp(a.data(), b.data(), a.size()) == 0;
}

long long LoginThrottle::wait_seconds(const std::string& key, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  const auto it = entries_.find(key);
  if (it == entries_.end() || it->second.failures < allowed_) return 0;
  const auto until = it->second.last + lockout_;
  if (now >= until) {
    entries_.erase(it);
    return 0;
  }
  return std::chrono::duration_cast<std::chrono::seconds>(until - now).count() + 1;
}

void LoginThrottle::failure(const std::string& key, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  // Bounded: a flood of distinct keys cannot grow the table without limit.
  if (entries_.size() > 100'000) entries_.clear();
  auto& e = entries_[key];
  if (e.failures == 0 || now - e.first > window_) {
    e.failures = 0;
    e.first = now;
  }
  ++e.failures;
  e.last = now;
}

void LoginThrottle::success(const std::string& key) {
  std::lock_guard lock(mutex_);
  entries_.erase(key);
}

void add_user(HistoryStore& store, const std::string& name, const std::string& role, const std::string& password,
              KdfCost cost) {
  if (const auto p = user_name_problem(name); !p.empty()) throw InputError({"user", 0, "name"}, p);
  if (!parse_role(role))
    throw InputError({"user " + name, 0, "role"},
                     "expected the role viewer, engineer or admin, found '" + printable(role) + "'");
  if (const auto p = password_problem(password); !p.empty()) throw InputError({"user " + name, 0, "password"}, p);
  store.put_user({name, role, hash_password(password, cost), ""});
}

}  // namespace mtcal::server
