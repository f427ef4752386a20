// Accounts of mtcal serve: roles, memory-hard password hashes (libsodium), random tokens, login throttling.
#pragma once

#include <chrono>
#include <cstddef>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "mtcal/io/history/store.hpp"

namespace mtcal::server {

// viewer: reads everything; engineer: also uploads, adds events, writes compensation; admin: also users.
enum class Role { Viewer = 0, Engineer = 1, Admin = 2 };
std::string_view to_string(Role r);
// "viewer", "engineer", "admin"; nullopt for anything else.
std::optional<Role> parse_role(std::string_view name);

// The cost of the password hash: libsodium's crypto_pwhash (Argon2id) limits. Interactive is
// libsodium's OPSLIMIT/MEMLIMIT_INTERACTIVE (64 MiB); Minimum is for tests only.
enum class KdfCost { Interactive, Moderate, Minimum };

// Argon2id hash string of a password (salt and parameters inside, "$argon2id$v=19$m=...").
// Throws Error when libsodium cannot allocate the memory.
std::string hash_password(std::string_view password, KdfCost cost = KdfCost::Interactive);
// Whether password matches a hash_password string (constant time in the password).
bool verify_password(std::string_view password, const std::string& hash);
// A password policy: at least 10 characters (NIST SP 800-63B, 5.1.1.2 asks for 8 at least).
// Empty when acceptable, else the reason.
std::string password_problem(std::string_view password);
// A user name: 1-64 printable ASCII characters without space, quotes, '<', '>' or '&'.
std::string user_name_problem(std::string_view name);

// 32 random bytes (libsodium's randombytes) as 64 lowercase hex digits.
std::string random_token();
// Constant-time comparison of two tokens.
bool tokens_equal(std::string_view a, std::string_view b);

// Login throttling: after `allowed` failures of one key (user name or client address) within
// `window`, further attempts of that key are refused until `lockout` has passed since the last
// failure. A success clears the key. Thread-safe.
class LoginThrottle {
 public:
  using Clock = std::chrono::steady_clock;
  LoginThrottle(int allowed = 5, std::chrono::seconds window = std::chrono::minutes(15),
                std::chrono::seconds lockout = std::chrono::minutes(15))
      : allowed_(allowed), window_(window), lockout_(lockout) {}
  // Seconds until the key may try again (0: may try now).
  long long wait_seconds(const std::string& key, Clock::time_point now = Clock::now());
  void failure(const std::string& key, Clock::time_point now = Clock::now());
  void success(const std::string& key);

 private:
  struct Entry {
    int failures = 0;
    Clock::time_point first, last;
  };
  int allowed_;
  std::chrono::seconds window_, lockout_;
  std::mutex mutex_;
  std::map<std::string, Entry> entries_;
};

// Creates or replaces a user in the store (the command's --add-user): checks name, role and
// password (InputError saying which and why) and stores the hash, never the password.
void add_user(HistoryStore& store, const std::string& name, const std::string& role, const std::string& password,
              KdfCost cost = KdfCost::Interactive);

}  // namespace mtcal::server
