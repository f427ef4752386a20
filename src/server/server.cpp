// mtcal serve: routes, sessions, CSRF, roles and the handlers of the pages and the JSON API.
#include "mtcal/server/server.hpp"

#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string_view>
#include <unordered_map>

#include <fmt/format.h>
#define ZLIB_CONST
#include <zlib.h>

#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/evaluation/tolerance.hpp"
#include "mtcal/history/analysis.hpp"
#include "mtcal/io/compensation/output.hpp"
#include "mtcal/io/compensation/output_json.hpp"
#include "mtcal/io/history/queries.hpp"
#include "mtcal/io/history/store.hpp"
#include "mtcal/io/instruments/acceptance_files.hpp"
#include "mtcal/io/instruments/iso230_files.hpp"
#include "mtcal/io/instruments/laser_files.hpp"
#include "mtcal/io/instruments/probing_files.hpp"
#include "mtcal/io/json/evaluation_json.hpp"
#include "mtcal/io/json/history_json.hpp"
#include "mtcal/io/json/json.hpp"
#include "mtcal/io/json/probing_json.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/system/sha256.hpp"
#include "mtcal/probing/rotary_probing.hpp"
#include "mtcal/report/history.hpp"
#include "mtcal/report/recorded.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/parse.hpp"
#include "mtcal/util/units.hpp"
#include "pages.hpp"
#include "zip.hpp"

// After Eigen (through the evaluation headers): httplib.h's system headers define macros that
// break Eigen's declarations when they come first.
#include <httplib.h>

namespace mtcal::server {

namespace {

namespace fs = std::filesystem;

constexpr const char* kSessionCookie = "mtcal_session";
constexpr const char* kLoginCookie = "mtcal_login";  // double-submit CSRF token of the login form

std::string now_utc_text(std::chrono::system_clock::time_point t = std::chrono::system_clock::now()) {
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(t.time_since_epoch()).count() % 1000;
  const std::time_t tt = std::chrono::system_clock::to_time_t(t);
  std::tm tm{};
  gmtime_r(&tt, &tm);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                     tm.tm_hour, tm.tm_min, tm.tm_sec, ms);
}

// The value of one cookie of a request's Cookie header ("a=b; c=d"); empty when absent.
std::string cookie_value(const httplib::Request& req, const std::string& name) {
  const std::string header = req.get_header_value("Cookie");
  std::size_t at = 0;
  while (at < header.size()) {
    std::size_t end = header.find(';', at);
    if (end == std::string::npos) end = header.size();
    std::string part = header.substr(at, end - at);
    const auto first = part.find_first_not_of(' ');
    part = first == std::string::npos ? "" : part.substr(first);
    if (part.size() > name.size() && part.compare(0, name.size(), name) == 0 && part[name.size()] == '=')
      return part.substr(name.size() + 1);
    at = end + 1;
  }
  return {};
}

// httplib compresses a response body whenever the client accepts it, with brotli at its default
// quality (11) when "br" is accepted, as every browser does: the fleet page of 1,000 machines
// then took 3.9 s (p50) instead of 65 ms (bench/serve_load.cpp). httplib compresses bodies and
// chunked content providers only, so the pages and the API's JSON go as a provider of known
// length, not compressed by httplib (the fleet is gzip'd here, once per change, when the client
// accepts it; a plant's reverse proxy may compress the others).
void send_uncompressed(httplib::Response& res, std::shared_ptr<const std::string> text, const char* type) {
  res.set_content_provider(text->size(), type, [text](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
    return sink.write(text->data() + offset, length);
  });
}
void send_uncompressed(httplib::Response& res, std::string body, const char* type) {
  send_uncompressed(res, std::make_shared<const std::string>(std::move(body)), type);
}

// Whether a request accepts a gzip'd response: "gzip" (or "x-gzip") among its Accept-Encoding
// codings, not refused with q=0 (RFC 9110, 12.5.3).
bool accepts_gzip(const httplib::Request& req) {
  const std::string header = req.get_header_value("Accept-Encoding");
  std::size_t at = 0;
  while (at <= header.size()) {
    std::size_t end = header.find(',', at);
    if (end == std::string::npos) end = header.size();
    std::string coding = header.substr(at, end - at);
    std::transform(coding.begin(), coding.end(), coding.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    coding.erase(std::remove(coding.begin(), coding.end(), ' '), coding.end());
    const auto semi = coding.find(';');
    const std::string name = coding.substr(0, semi);
    if (name == "gzip" || name == "x-gzip") {
      const auto q = semi == std::string::npos ? std::string::npos : coding.find("q=", semi);
      return q == std::string::npos || std::strtod(coding.c_str() + q + 2, nullptr) > 0;
    }
    at = end + 1;
  }
  return false;
}

// Text compressed as raw deflate (RFC 1951) that may be followed by more: ended by a sync flush
// (byte-aligned, no final block) unless last. Raw deflate streams of pieces so ended join into
// one stream (what pigz does), and their CRC-32s combine: a page whose large part is the same for
// every user is compressed once and only the user's part at each request.
struct Deflated {
  std::string data;
  uLong crc = 0;
  std::size_t size = 0;
};
Deflated deflate_piece(std::string_view text, bool last) {
  z_stream z{};
  // Level 1: the fleet's rows repeat themselves; more effort saves little and costs the request.
  if (deflateInit2(&z, 1, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw Error("zlib: cannot start deflate");
  Deflated out;
  out.size = text.size();
  out.crc = crc32(0L, reinterpret_cast<const Bytef*>(text.data()), static_cast<uInt>(text.size()));
  out.data.resize(deflateBound(&z, static_cast<uLong>(text.size())) + 16);
  z.next_in = reinterpret_cast<const Bytef*>(text.data());
  z.avail_in = static_cast<uInt>(text.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data.data());
  z.avail_out = static_cast<uInt>(out.data.size());
  const int rc = deflate(&z, last ? Z_FINISH : Z_SYNC_FLUSH);
  const bool ok = (last ? rc == Z_STREAM_END : rc == Z_OK) && z.avail_in == 0;
  out.data.resize(out.data.size() - z.avail_out);
  deflateEnd(&z);
  if (!ok) throw Error("zlib: cannot compress a page");
  return out;
}
// One gzip member (RFC 1952) of pieces in order, the last of them deflated with last = true.
std::string gzip_of(std::initializer_list<const Deflated*> pieces) {
  std::string out("\x1f\x8b\x08\x00\x00\x00\x00\x00\x00\x03", 10);  // deflate, no name, no time, Unix
  uLong crc = crc32(0L, nullptr, 0);
  std::size_t size = 0;
  for (const Deflated* p : pieces) {
    out += p->data;
    crc = crc32_combine(crc, p->crc, static_cast<z_off_t>(p->size));
    size += p->size;
  }
  for (const unsigned long v : {static_cast<unsigned long>(crc), static_cast<unsigned long>(size)})
    for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xff);
  return out;
}

// An error that becomes an HTTP status with one line of text (or {"error": ...} for the API).
struct HttpError {
  int status;
  std::string message;
};

// Store connections, one per request thread at a time: a HistoryStore is not shared between
// threads. A connection whose request failed with StoreError is dropped (a PostgreSQL server
// that restarted is reconnected on the next request).
class StorePool {
 public:
  explicit StorePool(std::string conn) : conn_(std::move(conn)) { idle_.push_back(open_history_store(conn_)); }
  class Lease {
   public:
    Lease(StorePool& p, std::unique_ptr<HistoryStore> s) : pool_(p), store_(std::move(s)) {}
    ~Lease() {
      if (store_ && !std::uncaught_exceptions()) pool_.give_back(std::move(store_));
    }
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    HistoryStore* operator->() { return store_.get(); }
    HistoryStore& operator*() { return *store_; }

   private:
    StorePool& pool_;
    std::unique_ptr<HistoryStore> store_;
  };
  Lease lease() {
    {
      std::lock_guard lock(mutex_);
      if (!idle_.empty()) {
        auto s = std::move(idle_.back());
        idle_.pop_back();
        return Lease(*this, std::move(s));
      }
    }
    return Lease(*this, open_history_store(conn_));
  }
  const std::string& connection() const { return conn_; }

 private:
  void give_back(std::unique_ptr<HistoryStore> s) {
    std::lock_guard lock(mutex_);
    if (idle_.size() < 64) idle_.push_back(std::move(s));
  }
  std::string conn_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<HistoryStore>> idle_;
};

// An evaluated upload waiting for its confirmation (bound to the session that uploaded it).
struct PendingUpload {
  std::string session_hash;
  CalibrationRecord record;
  Json result;
  std::chrono::steady_clock::time_point created;
  std::vector<ModelFile> files;  // kept with the record (an ISO 230-2 upload's runs)
};

// What an upload holds and the command that evaluates it (the record's command): ISO 230-2
// positioning runs (`mtcal iso230-2`: .dat, CSV, Renishaw .rtl/.rta), a ballbar trace (`mtcal
// ballbar`: CSV direction,angle_deg,radius_mm), probe contacts on a sphere at indexations of a
// rotary axis (`mtcal rotary-axis --contacts`: CSV).
struct UploadKind {
  const char* name;  // the form's value and the record's command
  const char* what;
  std::vector<const char*> extensions;
};
const std::vector<UploadKind>& upload_kinds() {
  static const std::vector<UploadKind> kKinds{
      {"iso230-2", "an ISO 230-2 file (.dat, .csv, .txt, .rtl, .rta)", {".dat", ".csv", ".rtl", ".rta", ".txt"}},
      {"ballbar", "a ballbar trace (.csv, .txt)", {".csv", ".txt"}},
      {"rotary-axis", "probe contacts (.csv)", {".csv"}},
  };
  return kKinds;
}

// The extension of an upload's name when its kind accepts it.
bool allowed_upload_name(const UploadKind& kind, const std::string& name, std::string& ext) {
  const auto dot = name.rfind('.');
  if (dot == std::string::npos) return false;
  ext = name.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return std::any_of(kind.extensions.begin(), kind.extensions.end(), [&](const char* e) { return ext == e; });
}

// A form field as a number: nullopt when empty; 400 naming the field when not a finite number
// within [lo, hi].
std::optional<double> number_field(const std::string& key, const std::string& text, double lo, double hi) {
  if (text.empty()) return std::nullopt;
  const auto v = parse_number(text);
  if (!v || !std::isfinite(*v) || *v < lo || *v > hi)
    throw HttpError{400, fmt::format("{}: expected a number from {:g} to {:g}, found '{}'", key, lo, hi, printable(text))};
  return *v;
}

// A private temporary folder, removed with everything in it when this goes (the readers take paths).
struct TempFolder {
  fs::path path;
  TempFolder() {
    std::string tmpl = (fs::temp_directory_path() / "mtcal-serve-XXXXXX").string();
    if (!::mkdtemp(tmpl.data())) throw Error("cannot create a temporary folder for an upload");
    path = tmpl;
  }
  ~TempFolder() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  // Writes content under `name` (ours, never the client's) and returns its path. Not
  // write_file_atomically: under the command, outputs are committed when it ends.
  std::string put(const std::string& name, const std::string& content) const {
    const std::string file = (path / name).string();
    std::ofstream out(file, std::ios::binary);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    if (!out.flush()) throw Error("cannot write an upload to a temporary file");
    return file;
  }
};

// A reader's InputError names our temporary path; the user knows the file by its name: 422.
[[noreturn]] void rethrow_named(const InputError& e, const std::string& path, const std::string& name) {
  std::string m = e.what();
  for (auto at = m.find(path); at != std::string::npos; at = m.find(path, at + name.size()))
    m.replace(at, path.size(), name);
  throw HttpError{422, m};
}

// A word of a command line as the commands show theirs (common.cpp's set_command_line): quoted
// for a POSIX shell where it holds a blank, a quote, a backslash, $ or `.
std::string shell_word(const std::string& a) {
  if (!a.empty() && a.find_first_of(" \t\"'\\$`") == std::string::npos) return a;
  std::string out = "'";
  for (const char c : a) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// The upload form's metadata as the command's `--meta KEY=VALUE` words, appended to `command`, and
// as the command's report shows them (a blank value shows nothing there).
ReportMetadata meta_words(const std::map<std::string, std::string>& meta, std::string& command) {
  ReportMetadata shown;
  for (const auto& [k, v] : meta) {
    if (v.find_first_not_of(" \t") != std::string::npos) shown.set(k, v, "upload");
    command += " --meta " + shell_word(k + "=" + v);
  }
  return shown;
}

// The name of an uploaded file as recorded: its last path component, printable, at most 100 characters.
std::string upload_display_name(const std::string& filename) {
  std::string base = filename;
  if (const auto slash = base.find_last_of("/\\"); slash != std::string::npos) base = base.substr(slash + 1);
  std::string out;
  for (const char c : base)
    if (static_cast<unsigned char>(c) >= 0x20 && c != 0x7f) out += c;
  if (out.size() > 100) out.resize(100);
  return out.empty() ? "upload" : out;
}

}  // namespace

struct Server::Impl {
  ServerOptions opt;
  StorePool pool;
  std::unique_ptr<httplib::Server> http;
  std::vector<Route> routes;
  LoginThrottle throttle;
  std::mutex pending_mutex;
  std::map<std::string, PendingUpload> pending;
  std::string dummy_hash;  // verified against for unknown users: a failed login costs the same time
  bool tls = false;
  // The fleet's ranking (ServerOptions' tolerances; none: no ranking) and its JSON, made again
  // when the ranker's ranking is a new one.
  std::unique_ptr<FleetRanker> ranker;
  std::mutex rank_mutex;
  std::shared_ptr<const FleetRanker::Ranking> rank_source;
  // The ranking as the fleet shows it: each machine's `history rank` entry (with its drift and
  // date out of tolerance) by machine name, and the notes. A hash map: the fleet page looks up
  // every machine (1,000 lookups in an ordered_json object are a linear scan each).
  struct FleetRanking {
    std::unordered_map<std::string, std::shared_ptr<const Json>> machines;
    Json notes;
  };
  std::shared_ptr<const FleetRanking> rank_cache;
  // run() and stop() (Server::stop says why they need more than httplib's own).
  enum class RunState { NotStarted, Starting, Returned };
  std::mutex run_mutex;
  std::condition_variable run_changed;
  RunState run_state = RunState::NotStarted;
  bool stop_requested = false, http_stopped = false;

  explicit Impl(ServerOptions o)
      : opt(std::move(o)),
        pool(opt.store),
        throttle(opt.login_attempts, std::chrono::seconds(900), std::chrono::seconds(opt.lockout_seconds)) {
    tls = !opt.tls_cert.empty() || !opt.tls_key.empty();
    if (tls) {
      if (opt.tls_cert.empty() || opt.tls_key.empty())
        throw InputError({"TLS", 0, ""}, "expected both a certificate and a key file, found only one");
      read_text_file(opt.tls_cert, "TLS certificate");  // a clear message for a missing file
      read_text_file(opt.tls_key, "TLS key");
      auto s = std::make_unique<httplib::SSLServer>(opt.tls_cert.c_str(), opt.tls_key.c_str());
      if (!s->is_valid())
        throw InputError({opt.tls_cert, 0, ""}, "cannot use the TLS certificate and key (not PEM, or not a pair)");
      http = std::move(s);
    } else {
      http = std::make_unique<httplib::Server>();
    }
    dummy_hash = hash_password("not a password of anyone", opt.kdf_cost);
    // "Q=V" or "Q=LO:HI" as `mtcal history rank --tolerance` reads them; the file read here.
    RankRequest rank_request;
    rank_request.tolerances = parse_history_tolerances(opt.tolerances, "tolerance");
    rank_request.tolerance_file = opt.tolerance_file;
    rank_request.options.threads = 1;  // a request thread: the other threads serve other requests
    rank_request.tolerance_source = "tolerance";
    if (!rank_request.tolerances.empty() || !rank_request.tolerance_file.empty())
      ranker = std::make_unique<FleetRanker>(std::move(rank_request), true);
    const int threads = std::max(1, opt.threads);
    http->new_task_queue = [threads] { return new httplib::ThreadPool(static_cast<std::size_t>(threads)); };
    http->set_payload_max_length(opt.max_upload);
    http->set_read_timeout(30, 0);
    http->set_write_timeout(30, 0);
    http->set_keep_alive_max_count(1000);
    http->set_default_headers({{"X-Content-Type-Options", "nosniff"},
                               {"X-Frame-Options", "DENY"},
                               {"Referrer-Policy", "no-referrer"},
                               {"Cache-Control", "no-store"}});
    http->set_exception_handler([this](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
      on_exception(req, res, ep);
    });
    http->set_error_handler([this](const httplib::Request& req, httplib::Response& res) {
      if (!res.body.empty()) return;
      const bool api = req.path.rfind("/api/", 0) == 0;
      std::string msg = res.status == 404   ? "no such page: " + printable(req.path)
                        : res.status == 413 ? fmt::format("the request is larger than {} bytes", opt.max_upload)
                                            : fmt::format("the request was refused ({})", res.status);
      send_error(res, api, res.status, msg);
    });
    // One policy for every response: scripts and styles from this server only (the trend
    // report, which inlines its scripts, sets its own).
    http->set_post_routing_handler([](const httplib::Request&, httplib::Response& res) {
      if (!res.has_header("Content-Security-Policy"))
        res.set_header("Content-Security-Policy",
                       "default-src 'self'; script-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' "
                       "data:; frame-ancestors 'none'; form-action 'self'");
    });
    register_routes();
    // The fleet's ranking and its page made once here (the ranking: about a second for 1,000
    // machines on a loaded 2-core machine), so that no request pays for them; afterwards a new
    // record re-reads and makes again its machine's part only.
    {
      auto store = pool.lease();
      fleet_view(*store);
    }
  }

  // ---- responses -------------------------------------------------------------------------

  void send_error(httplib::Response& res, bool api, int status, const std::string& message) {
    res.status = status;
    if (api)
      res.set_content(Json{{"error", message}}.dump() + "\n", "application/json");
    else
      res.set_content(error_page(status, message), "text/html; charset=utf-8");
  }

  void on_exception(const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
    const bool api = req.path.rfind("/api/", 0) == 0;
    try {
      std::rethrow_exception(ep);
    } catch (const HttpError& e) {
      send_error(res, api, e.status, e.message);
    } catch (const StoreError& e) {
      send_error(res, api, 503, std::string("the history store is unavailable: ") + e.what());
    } catch (const LimitError& e) {
      send_error(res, api, 413, e.what());
    } catch (const InputError& e) {
      send_error(res, api, 400, e.what());
    } catch (const std::exception& e) {
      send_error(res, api, 500, std::string("internal error: ") + e.what());
    } catch (...) {
      send_error(res, api, 500, "internal error");
    }
  }

  std::string cookie_attributes(int max_age) const {
    return fmt::format("; Path=/; HttpOnly; SameSite=Strict; Max-Age={}{}", max_age, tls ? "; Secure" : "");
  }

  // ---- sessions ----------------------------------------------------------------------------

  struct Context {
    SessionEntry session;
    Role role = Role::Viewer;
  };

  std::optional<Context> session_of(const httplib::Request& req) {
    const std::string id = cookie_value(req, kSessionCookie);
    if (id.size() != 64 || id.find_first_not_of("0123456789abcdef") != std::string::npos) return std::nullopt;
    auto store = pool.lease();
    auto s = store->find_session(sha256_hex(id), now_utc_text());
    if (!s) return std::nullopt;
    const auto user = store->find_user(s->user);
    if (!user) return std::nullopt;
    const auto role = parse_role(user->role);
    if (!role) return std::nullopt;
    return Context{*s, *role};
  }

  // Registers a route: the one list both the router and the tests use.
  using Handler = std::function<void(const httplib::Request&, httplib::Response&, const Context*)>;
  void add(Route r, Handler h) {
    routes.push_back(r);
    auto wrapped = [this, r, h](const httplib::Request& req, httplib::Response& res) {
      // The time spent here (session check and handler; not httplib's queue, parsing or sending)
      // as a Server-Timing header (W3C Server Timing): the load test tells the handler's time from
      // the time a request waits or travels.
      const auto start = std::chrono::steady_clock::now();
      struct Timing {
        httplib::Response& res;
        std::chrono::steady_clock::time_point start;
        ~Timing() {
          const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
          res.set_header("Server-Timing", fmt::format("app;dur={:.2f}", ms));
        }
      } timing{res, start};
      if (r.is_public) return h(req, res, nullptr);
      const auto ctx = session_of(req);
      if (!ctx) {
        if (r.api || r.method != "GET") return send_error(res, r.api, 401, "log in first");
        res.status = 303;
        res.set_header("Location", "/login");
        return;
      }
      if (static_cast<int>(ctx->role) < static_cast<int>(r.min_role))
        return send_error(res, r.api, 403,
                          fmt::format("this needs the role {} (you are {})", to_string(r.min_role), to_string(ctx->role)));
      if (r.method == "POST") {
        // The token of the session: a form field, or the X-CSRF-Token header of an API call.
        std::string token = req.get_header_value("X-CSRF-Token");
        if (token.empty() && req.has_param("csrf")) token = req.get_param_value("csrf");
        if (token.empty() && req.has_file("csrf")) token = req.get_file_value("csrf").content;
        if (!tokens_equal(token, ctx->session.csrf_token))
          return send_error(res, r.api, 403, "the form's CSRF token is missing or wrong: reload the page");
      }
      h(req, res, &*ctx);
    };
    const std::string pattern = r.path;
    if (r.method == "GET")
      http->Get(pattern, wrapped);
    else
      http->Post(pattern, wrapped);
  }

  // ---- helpers -----------------------------------------------------------------------------

  static std::string param(const httplib::Request& req, const std::string& key, std::size_t max = 1000) {
    std::string v;
    if (req.has_param(key))
      v = req.get_param_value(key);
    else if (req.has_file(key))
      v = req.get_file_value(key).content;
    if (v.size() > max) throw HttpError{400, fmt::format("the field {} is longer than {} characters", key, max)};
    return v;
  }

  static std::string required(const httplib::Request& req, const std::string& key) {
    std::string v = param(req, key);
    if (v.empty()) throw HttpError{400, "the field " + key + " is missing"};
    return v;
  }

  static void send_json(httplib::Response& res, const Json& j) {
    send_uncompressed(res, j.dump(2) + "\n", "application/json");
  }

  PageUser page_user(const Context* c) const {
    if (!c) return {};
    return {c->session.user, std::string(to_string(c->role)), c->session.csrf_token,
            static_cast<int>(c->role) >= static_cast<int>(Role::Engineer), c->role == Role::Admin};
  }

  // The fleet ranking as `mtcal history rank --json` gives it (FleetRanker: rank_store's series,
  // bands and ranking), by machine; null without tolerances. A series that history rank would
  // refuse (a unit that is not a length under a tolerance file's limit in µm) is left out and
  // named in "notes". The ranker reads the machines' revisions and fits again only the series of
  // machines whose records changed since the last page (a fleet of 1,000 machines: 1,000 series
  // read and fitted otherwise, after every upload). Each machine's entry is kept and made again
  // only for the machines the ranker says changed and those whose rank moved: after an upload
  // one machine's entry, not 1,000 (under the mixed load the fleet page followed every upload
  // and made all of them again; docs/serve.md, Load). The fleet's kept rows compare entries by
  // identity first.
  std::shared_ptr<const FleetRanking> ranking(HistoryStore& store) {
    if (!ranker) return nullptr;
    std::lock_guard lock(rank_mutex);  // one ranking at a time; the others wait for it
    const auto ranked = ranker->rank(store);
    if (rank_cache && ranked == rank_source) return rank_cache;
    // The kept entries stand for the ranking just before this one only.
    const bool follows = rank_cache && rank_source && ranked->serial == rank_source->serial + 1;
    const auto& changed = ranked->changed;
    auto out = std::make_shared<FleetRanking>();
    out->notes = ranked->notes;
    out->machines.reserve(ranked->ranking.machines.size());
    for (const auto& rm : ranked->ranking.machines) {
      if (follows && !std::binary_search(changed.begin(), changed.end(), rm.machine))
        if (const auto kept = rank_cache->machines.find(rm.machine);
            kept != rank_cache->machines.end() && kept->second->at("rank").get<std::size_t>() == rm.rank) {
          out->machines.emplace(rm.machine, kept->second);
          continue;
        }
      out->machines.emplace(rm.machine, std::make_shared<const Json>(fleet_rank_entry(rm)));
    }
    rank_source = ranked;
    rank_cache = out;
    return out;
  }

  // A machine's entry of the fleet's ranking: its `history rank --json` entry, with the drift
  // state of the deciding quantity (the first) and the earliest date a line leaves its
  // tolerance among the machine's quantities.
  static Json fleet_rank_entry(const RankedMachine& rm) {
    Json m = to_json(rm);
    Json drift = m["quantities"][0]["crossing"]["status"];
    Json date = nullptr;
    for (const auto& q : m["quantities"]) {
      const Json& c = q["crossing"];
      if (c["status"] == "predicted" && c["date"].is_string() &&
          (date.is_null() || c["date"].get<std::string>() < date.get<std::string>()))
        date = c["date"];
    }
    m["drift"] = std::move(drift);
    m["out_of_tolerance_on"] = std::move(date);
    return m;
  }

  // ---- the fleet, kept between requests ----------------------------------------------------
  //
  // The fleet page of 1,000 machines took 50 to 60 ms in its handler (the JSON and the HTML of
  // every machine made again at every request; docs/serve.md, Load). Each machine's part (its
  // entry of /api/fleet as text and its rows of the table) is kept with what it was made from:
  // its latest calibrations, its interval, its ranking entry and the time its ages count to. A
  // request reads those inputs from the store (latest_records, the intervals and the ranker's
  // revision check: about 2 ms for 1,000 machines) and makes again only the parts whose inputs
  // differ, whoever wrote them (this server, another server or a command on the same store):
  // a page is never older than the store at the request. Ages count to `as_of`, the same for
  // every row, renewed when it is kFleetClock old (then every row is made again).
  static constexpr std::chrono::seconds kFleetClock{60};
  struct FleetPart {
    std::vector<LatestCalibration> latest;  // this machine's, by command
    int interval = 0;
    bool interval_own = false;
    std::shared_ptr<const Json> rank;  // its entry of the ranking (null: not ranked)
    bool overdue = false;
    std::string json;   // its entry of /api/fleet's "machines" as dump(2) writes it there
    std::string html;   // its rows of the fleet table
  };
  struct FleetView {
    std::shared_ptr<const std::string> json;  // /api/fleet's body
    std::shared_ptr<const std::string> html;  // the fleet page's content (fleet_page_body)
    // Made at the first request that accepts gzip: json gzip'd, html deflated as a middle piece.
    std::shared_ptr<const std::string> json_gzip;
    std::shared_ptr<const Deflated> html_deflated;
  };
  std::mutex fleet_mutex;  // guards the members below; one fleet request updates them at a time
  std::unordered_map<std::string, std::shared_ptr<const FleetPart>> fleet_parts;  // by machine
  std::vector<std::shared_ptr<const FleetPart>> fleet_order;  // the parts of the last view, in order
  std::optional<std::chrono::system_clock::time_point> fleet_as_of;
  std::shared_ptr<const FleetRanking> fleet_rank;  // the ranking the parts were made with
  FleetView fleet_view_kept;

  // Ranking entries kept from the last ranking are the same objects; others are compared.
  static bool same_rank(const std::shared_ptr<const Json>& a, const std::shared_ptr<const Json>& b) {
    return a == b || (a && b && *a == *b);
  }

  static bool same_latest(const std::vector<LatestCalibration>& a, const LatestCalibration* b, std::size_t n) {
    if (a.size() != n) return false;
    for (std::size_t i = 0; i < n; ++i)
      if (a[i].command != b[i].command || a[i].record_id != b[i].record_id || a[i].measured_at != b[i].measured_at ||
          a[i].count != b[i].count || a[i].machine != b[i].machine)
        return false;
    return true;
  }

  // One machine's entry of the fleet: its latest calibration per command, overdue after its
  // interval (an admin's, else interval_days) counted to as_of, and its ranking entry.
  std::shared_ptr<const FleetPart> fleet_part(const LatestCalibration* latest, std::size_t n, int interval, bool own,
                                              const std::shared_ptr<const Json>& rank, bool ranked,
                                              std::chrono::system_clock::time_point as_of) const {
    auto part = std::make_shared<FleetPart>();
    part->latest.assign(latest, latest + n);
    part->interval = interval;
    part->interval_own = own;
    part->rank = rank;
    Json m = Json::object();
    m["machine"] = latest[0].machine;
    m["interval_days"] = interval;
    m["interval_own"] = own;
    m["calibrations"] = Json::array();
    m["overdue"] = false;
    m["rank"] = rank ? *rank : Json();
    for (std::size_t i = 0; i < n; ++i) {
      const auto& l = latest[i];
      bool overdue = false;
      std::optional<double> age_days;
      try {
        const auto at = parse_history_time(l.measured_at, "record " + l.record_id);
        age_days = std::chrono::duration<double>(as_of - at).count() / 86400.0;
        overdue = *age_days > interval;
      } catch (const InputError&) {
      }
      m["calibrations"].push_back({{"command", l.command},
                                   {"last", l.measured_at},
                                   {"record", l.record_id},
                                   {"count", l.count},
                                   {"age_days", number_or_null(age_days)},
                                   {"overdue", overdue}});
      if (overdue) m["overdue"] = true;
    }
    part->overdue = m["overdue"].get<bool>();
    part->html = fleet_machine_rows(m, ranked);
    // An element of the array at depth 2 of the whole document: its lines indented 4 more.
    const std::string text = m.dump(2);
    part->json.reserve(text.size() + text.size() / 8);
    for (const char c : text) {
      part->json += c;
      if (c == '\n') part->json += "    ";
    }
    return part;
  }

  // Where a fleet request's time goes, in ms, sent as Server-Timing metrics beside "app" (the
  // load test reports them): waiting for another fleet request (wait), the ranking (rank), the
  // other inputs read from the store (read), the kept parts compared and made again (parts), the
  // documents joined (join), their compression (gzip).
  struct FleetTiming {
    double wait = 0, rank = 0, read = 0, parts = 0, join = 0, gzip = 0;
    std::string header() const {
      return fmt::format("wait;dur={:.2f}, rank;dur={:.2f}, read;dur={:.2f}, parts;dur={:.2f}, join;dur={:.2f}, "
                         "gzip;dur={:.2f}",
                         wait, rank, read, parts, join, gzip);
    }
  };
  // Milliseconds since `t`, and `t` moved to now.
  static double lap(std::chrono::steady_clock::time_point& t) {
    const auto now = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - t).count();
    t = now;
    return ms;
  }

  // The fleet now (/api/fleet's body and the page's content): per machine its latest
  // calibration per command, overdue after its interval, and its ranking (tolerances given).
  FleetView fleet_view(HistoryStore& store, bool json_gzip = false, bool html_deflated = false,
                       FleetTiming* timing = nullptr) {
    FleetTiming ignored;
    FleetTiming& t = timing ? *timing : ignored;
    auto at = std::chrono::steady_clock::now();
    std::lock_guard lock(fleet_mutex);
    t.wait = lap(at);
    fleet_update(store, t);
    at = std::chrono::steady_clock::now();
    auto& v = fleet_view_kept;
    if (json_gzip && !v.json_gzip) {
      const Deflated d = deflate_piece(*v.json, true);
      v.json_gzip = std::make_shared<const std::string>(gzip_of({&d}));
    }
    if (html_deflated && !v.html_deflated) v.html_deflated = std::make_shared<const Deflated>(deflate_piece(*v.html, false));
    t.gzip = lap(at);
    return v;
  }
  // fleet_view's update of the kept parts (fleet_mutex held).
  void fleet_update(HistoryStore& store, FleetTiming& t) {
    auto at = std::chrono::steady_clock::now();
    // The inputs, read at every request (the ranking's revisions first, inside ranking()).
    const auto rank = ranking(store);
    t.rank = lap(at);
    const auto latest = store.latest_calibrations();
    std::map<std::string, int> intervals;
    for (const auto& i : store.machine_intervals()) intervals[i.machine] = i.days;
    t.read = lap(at);
    const auto now = std::chrono::system_clock::now();
    const bool new_clock = !fleet_as_of || now - *fleet_as_of >= kFleetClock || now < *fleet_as_of;
    if (new_clock) fleet_as_of = now;
    const bool new_rank = rank != fleet_rank;
    bool changed = new_clock || new_rank || !fleet_view_kept.json;
    std::vector<std::shared_ptr<const FleetPart>> order;
    std::unordered_map<std::string, std::shared_ptr<const FleetPart>> parts;
    for (std::size_t b = 0, e = 0; b < latest.size(); b = e) {
      const std::string& name = latest[b].machine;
      for (e = b + 1; e < latest.size() && latest[e].machine == name;) ++e;
      const auto own = intervals.find(name);
      const int interval = own != intervals.end() ? own->second : opt.interval_days;
      std::shared_ptr<const Json> r;
      if (rank)
        if (const auto it = rank->machines.find(name); it != rank->machines.end()) r = it->second;
      std::shared_ptr<const FleetPart> part;
      if (const auto kept = fleet_parts.find(name); kept != fleet_parts.end() && !new_clock &&
                                                    kept->second->interval == interval &&
                                                    kept->second->interval_own == (own != intervals.end()) &&
                                                    same_latest(kept->second->latest, &latest[b], e - b) &&
                                                    (!new_rank || same_rank(kept->second->rank, r)))
        part = kept->second;
      else
        part = fleet_part(&latest[b], e - b, interval, own != intervals.end(), r, rank != nullptr, *fleet_as_of);
      if (order.size() >= fleet_order.size() || fleet_order[order.size()] != part) changed = true;
      order.push_back(part);
      parts.emplace(name, std::move(part));
    }
    if (order.size() != fleet_order.size()) changed = true;
    fleet_parts = std::move(parts);
    fleet_rank = rank;
    t.parts = lap(at);
    if (!changed) return;
    fleet_order = std::move(order);
    // The document as Json::dump(2) writes it, the machines' entries put in as kept.
    Json head = Json::object();
    head["store"] = store.describe();
    head["interval_days"] = opt.interval_days;
    head["ranked"] = rank != nullptr;
    head["rank_notes"] = rank ? rank->notes : Json::array();
    head["as_of"] = now_utc_text(*fleet_as_of);
    std::string json = head.dump(2);
    json.resize(json.size() - 2);  // "\n}"
    std::size_t size = json.size() + 64, rows_size = 0, overdue = 0;
    for (const auto& p : fleet_order) {
      size += p->json.size() + 6;
      rows_size += p->html.size();
      if (p->overdue) ++overdue;
    }
    json.reserve(size);
    json += ",\n  \"machines\": [";
    for (std::size_t i = 0; i < fleet_order.size(); ++i) {
      json += i ? ",\n    " : "\n    ";
      json += fleet_order[i]->json;
    }
    json += fleet_order.empty() ? "]\n}\n" : "\n  ]\n}\n";
    std::string rows;
    rows.reserve(rows_size);
    for (const auto& p : fleet_order) rows += p->html;
    fleet_view_kept = {std::make_shared<const std::string>(std::move(json)),
                       std::make_shared<const std::string>(fleet_page_body(head, fleet_order.size(), overdue, rows)),
                       nullptr, nullptr};
    t.join = lap(at);
  }

  // What `history trend --json` gives for a machine: every parameter and figure, no tolerances.
  std::pair<MachineTrends, std::vector<CalibrationRecord>> trends(HistoryStore& store, const std::string& machine) {
    RecordFilter f;
    f.machine = machine;
    auto records = store.list(f);
    if (records.empty()) throw HttpError{404, "no records of machine '" + printable(machine) + "'"};
    MachineTrends m;
    m.machine = machine;
    m.serial = records.back().machine_serial;
    std::set<std::string> params, figs;
    for (const auto& r : records) {
      for (const auto& p : r.parameters)
        if (params.insert(p.name).second)
          m.series.push_back(trend_from_series(p.name, false, store.parameter_series(machine, p.name)));
      for (const auto& x : r.figures)
        if (figs.insert(x.name).second)
          m.series.push_back(trend_from_series(x.name, true, store.figure_series(machine, x.name)));
    }
    m.events = store.events(machine);
    return {std::move(m), std::move(records)};
  }

  Json machine_json(HistoryStore& store, const std::string& machine) {
    RecordFilter f;
    f.machine = machine;
    return machine_json(store, machine, store.list(f));
  }
  Json machine_json(HistoryStore& store, const std::string& machine, const std::vector<CalibrationRecord>& records) {
    if (records.empty()) throw HttpError{404, "no records of machine '" + printable(machine) + "'"};
    Json recs = Json::array();
    for (const auto& r : records) {
      Json figs = Json::object();
      for (const auto& x : r.figures) figs[x.name] = {{"value", x.value}, {"unit", x.unit}};
      std::string by;
      for (const auto& a : store.audit(r.id)) by = a.user;
      recs.push_back({{"id", r.id},
                      {"command", r.command},
                      {"measured_at", r.measured_at},
                      {"recorded_at", r.recorded_at},
                      {"recorded_by", by},
                      {"figures", figs},
                      {"parameters", r.parameters.size()}});
    }
    Json evs = Json::array();
    for (const auto& e : store.events(machine)) {
      std::string by;
      for (const auto& a : store.audit(e.id)) by = a.user;
      evs.push_back(
          {{"id", e.id}, {"date", e.date}, {"kind", std::string(to_string(e.kind))}, {"note", e.note}, {"added_by", by}});
    }
    return {{"machine", machine}, {"serial", records.back().machine_serial}, {"records", recs}, {"events", evs}};
  }

  // history diff --json of two records.
  Json diff_json(HistoryStore& store, const std::string& a_id, const std::string& b_id) {
    auto get = [&](const std::string& id) {
      auto r = store.get(id);
      if (!r) throw HttpError{404, "no record '" + printable(id) + "' in the store"};
      return *r;
    };
    const CalibrationRecord a = get(a_id), b = get(b_id);
    Json j = to_json(diff_records(a, b));
    j["machines"] = {a.machine_name, b.machine_name};
    j["measured_at"] = {a.measured_at, b.measured_at};
    return j;
  }

  // An uploaded instrument file evaluated as its command does, with the form's metadata (the
  // --meta keys) as the record's: ISO 230-2 runs as `mtcal history import FILE --meta ...`
  // (read_positioning_file, format auto, unit mm; evaluate_positioning; the file's metadata
  // under "metadata"), a ballbar trace as `mtcal ballbar TRACE --radius R --plane P [--feed F]
  // --record` (evaluate_ballbar, diagnose_ballbar), probe contacts as `mtcal rotary-axis --axis A
  // --contacts FILE --sphere-diameter D --stylus-diameter d --record` (method both). Nothing is
  // stored here.
  PendingUpload evaluate_upload(const httplib::Request& req, const Context& ctx) {
    const std::string kind_name = param(req, "kind", 40).empty() ? std::string("iso230-2") : param(req, "kind", 40);
    const auto kind = std::find_if(upload_kinds().begin(), upload_kinds().end(),
                                   [&](const UploadKind& k) { return kind_name == k.name; });
    if (kind == upload_kinds().end())
      throw HttpError{400, "kind: expected iso230-2, ballbar or rotary-axis, found '" + printable(kind_name) + "'"};
    if (!req.has_file("file")) throw HttpError{400, "expected an instrument file in the field 'file', found none"};
    const auto file = req.get_file_value("file");
    const std::string name = upload_display_name(file.filename);
    std::string ext;
    if (!allowed_upload_name(*kind, name, ext))
      throw HttpError{415, std::string("expected ") + kind->what + ", found '" + printable(name) + "'"};
    if (file.content.empty()) throw HttpError{400, "the file '" + printable(name) + "' is empty"};
    std::map<std::string, std::string> meta;
    for (const auto& f : metadata_fields()) {
      const std::string key(f.key);
      const std::string v = param(req, key, 500);
      if (!v.empty()) meta[key] = v;
    }
    if (!meta.count("machine")) throw HttpError{400, "the field machine is missing"};
    if (const auto d = meta.find("date"); d != meta.end() && !is_iso8601(d->second))
      throw HttpError{400, "date: expected an ISO 8601 date (2026-11-25), found '" + printable(d->second) + "'"};
    const TempFolder dir;
    const std::string path = dir.put("upload" + ext, file.content);
    const std::vector<InputHash> inputs{{name, sha256_hex(file.content)}};
    Json shown;
    CalibrationRecord rec;
    std::vector<ModelFile> files;
    try {
      if (kind_name == "iso230-2") {
        const PositioningRuns runs = read_positioning_file(path, "auto", "mm", "");
        Json r = to_json(evaluate_positioning(runs));
        Json m = Json::object();
        for (const auto& [k, v] : runs.metadata) m[k] = v;
        r["metadata"] = m;
        rec = record_from_result("iso230-2", r.dump(), meta, inputs, name);
        shown = r;
        shown["warnings"] = runs.warnings;
        // The runs kept with the record and the command line of the same evaluation, so that
        // the record page shows the report `mtcal iso230-2 NAME --meta ... --report F` writes
        // (report/recorded.hpp): the form's metadata, the file's header filling it in.
        if (is_utf8(file.content)) {
          std::string command = "mtcal iso230-2 " + shell_word(name);
          ReportMetadata shown_meta = meta_words(meta, command);
          shown_meta.fill_missing_from(laser_report_metadata(runs));
          rec.invocation = json_text(positioning_invocation(command, name, "auto", "mm", "", 0, {}, shown_meta));
          files.push_back({inputs[0].sha256, "measurements", file.content});
        }
      } else if (kind_name == "ballbar") {
        const auto radius = number_field("radius", param(req, "radius", 40), 1e-3, 1e5);
        if (!radius) throw HttpError{400, "radius: expected the nominal radius of the test (the ballbar's length, mm)"};
        const std::string plane = param(req, "plane", 8).empty() ? std::string("XY") : param(req, "plane", 8);
        if (plane != "XY" && plane != "YZ" && plane != "ZX")
          throw HttpError{400, "plane: expected XY, YZ or ZX, found '" + printable(plane) + "'"};
        const double feed = number_field("feed", param(req, "feed", 40), 0, 1e6).value_or(0.0);
        BallbarOptions bo;
        bo.nominal_radius = *radius;
        const BallbarTrace t = read_ballbar_csv(path);
        const auto e = evaluate_ballbar(t, bo);
        const TraceDiagnosis diagnosis = diagnose_ballbar(t, bo, plane);
        if (feed > 0 && !meta.count("feed")) meta["feed"] = fmt::format("{:g} mm/min", feed);  // as the command does
        const Json r = to_json(e, diagnosis, plane, *radius, feed);
        rec = record_from_result("ballbar", r.dump(), meta, inputs, name);
        shown = r;
        // As for ISO 230-2 runs: the report of `mtcal ballbar NAME --radius R --plane P [--feed F] --meta ...`.
        if (is_utf8(file.content)) {
          std::string command = "mtcal ballbar " + shell_word(name) + fmt::format(" --radius {:g} --plane {}", *radius, plane);
          if (feed > 0) command += fmt::format(" --feed {:g}", feed);
          const ReportMetadata shown_meta = meta_words(meta, command);  // feed too: the form's text wins, as --meta does
          rec.invocation = json_text(ballbar_invocation(command, name, plane, *radius, feed, 0, 0, "", {}, shown_meta));
          files.push_back({inputs[0].sha256, "measurements", file.content});
        }
      } else {
        // Not "axis": that is a metadata key (the axis an ISO 230-2 test measured).
        const std::string axis = param(req, "rotary_axis", 4);
        if (axis.size() != 1 || axis[0] < 'A' || axis[0] > 'C')
          throw HttpError{400, "rotary_axis: expected A, B or C, found '" + printable(axis) + "'"};
        const auto sphere = number_field("sphere_diameter", param(req, "sphere_diameter", 40), 1e-3, 1e4);
        if (!sphere) throw HttpError{400, "sphere_diameter: expected the calibration sphere's diameter (mm)"};
        const double stylus = number_field("stylus_diameter", param(req, "stylus_diameter", 40), 0, 1e3).value_or(0.0);
        IndexedCentres centres = centres_from_contacts(read_contacts_csv(path, axis[0]), SphereProbing{*sphere, stylus, 0.01});
        if (centres.centres.size() > opt.max_indexations)
          throw HttpError{413, fmt::format("{} indexations are more than this server evaluates ({}); evaluate with mtcal "
                                           "rotary-axis and record with mtcal history import",
                                           centres.centres.size(), opt.max_indexations)};
        const RotaryAxisResult r =
            locate_rotary_axis(NominalRotaryAxis::by_letter(axis[0]), std::move(centres),
                               RotaryAxisOptions{true, true, TriplesOptions{2.0, 40, 1}, 0.1});
        if (!r.located)
          throw HttpError{422, fmt::format("the centres turn about a line {:.1f} deg from the nominal direction of {}: no "
                                           "location errors (wrong axis?)",
                                           r.line.tilt * 180 / 3.14159265358979323846, axis)};
        const Json j = to_json(r);
        rec = record_from_result("rotary-axis", j.dump(), meta, inputs, name);
        shown = j;
        // As for ISO 230-2 runs: the report of `mtcal rotary-axis --axis A --contacts NAME
        // --sphere-diameter D [--stylus-diameter d] --meta ...` (the command's defaults otherwise).
        if (is_utf8(file.content)) {
          std::string command = "mtcal rotary-axis --axis " + axis + " --contacts " + shell_word(name) +
                                fmt::format(" --sphere-diameter {:g}", *sphere);
          if (stylus > 0) command += fmt::format(" --stylus-diameter {:g}", stylus);
          const ReportMetadata shown_meta = meta_words(meta, command);
          rec.invocation = json_text(rotary_invocation(command, name, axis[0], "csv", "", *sphere, stylus, 0.01,
                                                       std::nullopt, "both", 2.0, 40, shown_meta));
          files.push_back({inputs[0].sha256, "measurements", file.content});
        }
      }
    } catch (const InputError& e) {
      rethrow_named(e, path, name);
    }
    PendingUpload p;
    p.session_hash = ctx.session.id_hash;
    p.record = std::move(rec);
    p.result = std::move(shown);
    p.created = std::chrono::steady_clock::now();
    p.files = std::move(files);
    return p;
  }

  // The model of a recorded result (schema version 5, docs/serve.md): its machine file and the
  // parameter files that follow it among its inputs (the order of -m and --params), from the
  // store's model files, then the record's estimated parameters by name, converted from the
  // record's units to the machine's: what `mtcal compensate -m MACHINE --params PRIOR...
  // --params IDENTIFY_OUT` loads for an identification.
  Machine recorded_machine(HistoryStore& store, const std::string& id) {
    const auto r = store.get(id);
    if (!r) throw HttpError{404, "no record '" + printable(id) + "' in the store"};
    std::optional<ModelFile> machine;
    std::size_t at = 0;
    for (; at < r->inputs.size(); ++at) {
      auto f = store.model_file(r->inputs[at].sha256);
      if (f && f->kind == "machine") {
        machine = std::move(f);
        break;
      }
    }
    if (!machine) {
      std::string missing;
      for (const auto& in : r->inputs)
        missing += (missing.empty() ? "" : "; ") + printable(in.path) + " (SHA-256 " + in.sha256 + ")";
      throw HttpError{404, fmt::format("record {} ({}, {}) has no machine file in the store: none of its inputs is a "
                                       "stored model file ({}). Records made before schema version 5, by a command "
                                       "without -m, or imported from an older export hold none: write compensation "
                                       "from an uploaded machine file instead",
                                       r->id, r->command, r->machine_name,
                                       missing.empty() ? std::string("it names no input files") : "missing: " + missing)};
    }
    try {
      Machine m = parse_machine(machine->content, r->inputs[at].path);
      for (std::size_t i = at + 1; i < r->inputs.size(); ++i) {
        const auto f = store.model_file(r->inputs[i].sha256);
        if (!f || f->kind != "parameters") break;
        apply_parameter_file(m, f->content, r->inputs[i].path);
      }
      for (const auto& p : r->parameters) {
        const auto index = m.parameter_index(p.name);
        if (!index)
          throw HttpError{422, fmt::format("record {}: its parameter {} is not a parameter of the machine {} of its "
                                           "machine file {}",
                                           r->id, printable(p.name), m.name, printable(r->inputs[at].path))};
        const std::string internal = m.parameters()[*index].unit;
        // The same unit: the value as recorded, bit for bit (identify's parameters are in the
        // machine's internal units); else converted as a typed value is.
        const double v = p.unit == internal || p.unit.empty()
                             ? p.value
                             : parse_in_unit(fmt::format("{:.17g} {}", p.value, p.unit), internal,
                                             {"record " + r->id, 0, "parameters " + p.name});
        m.set_parameter(*index, v);
      }
      return m;
    } catch (const InputError& e) {
      throw HttpError{422, e.what()};
    }
  }

  // "write compensation": a machine file (and parameter files) turned into a compensation
  // target's files as `mtcal compensate -m MACHINE --params P... --format F [--points N] --out DIR`
  // does (the same target.run); returned as a zip of DIR's files under the folder DIR. With the
  // field `record`, the machine is that record's (recorded_machine) instead of an uploaded one.
  std::pair<std::string, TargetOutput> compensation(const httplib::Request& req) {
    const std::string record = param(req, "record", 100);
    if (record.empty() && !req.has_file("machine_file"))
      throw HttpError{400, "expected a machine file in the field 'machine_file' or a record in 'record', found neither"};
    const std::string format = required(req, "format");
    if (std::none_of(compensation_targets().begin(), compensation_targets().end(),
                     [&](const CompensationTarget& t) { return t.name == format; }))
      throw HttpError{400, "format: expected one of the compensation targets, found '" + printable(format) + "'"};
    CompensationOptions co;
    co.threads = 1;
    if (const auto points = number_field("points", param(req, "points", 20), 2, 10000))
      co.points = static_cast<std::size_t>(*points);
    try {
      Machine m;
      if (!record.empty()) {
        auto store = pool.lease();
        m = recorded_machine(*store, record);
      } else {
        const auto mf = req.get_file_value("machine_file");
        m = parse_machine(mf.content, upload_display_name(mf.filename));
        // Parameter files in the order given (each error given replaces the machine's, as --params),
        // in either form --params reads: an Etalon exchange file or mtcal's YAML.
        const auto [from, to] = req.files.equal_range("params");
        for (auto p = from; p != to; ++p)
          if (!p->second.content.empty())
            apply_parameter_file(m, p->second.content, upload_display_name(p->second.filename));
      }
      TargetOutput out = compensation_target(format).run(m, co);
      return {m.name, std::move(out)};
    } catch (const InputError& e) {
      throw HttpError{422, e.what()};
    }
  }

  std::string keep_pending(PendingUpload p) {
    std::lock_guard lock(pending_mutex);
    const auto now = std::chrono::steady_clock::now();
    std::erase_if(pending, [&](const auto& kv) { return now - kv.second.created > std::chrono::hours(1); });
    if (pending.size() >= 1000) throw HttpError{503, "too many uploads wait for confirmation; try again later"};
    std::string token = random_token();
    pending.emplace(token, std::move(p));
    return token;
  }

  PendingUpload take_pending(const std::string& token, const Context& ctx) {
    std::lock_guard lock(pending_mutex);
    const auto it = pending.find(token);
    if (it == pending.end() || it->second.session_hash != ctx.session.id_hash)
      throw HttpError{404, "no upload waits for confirmation under this token (expired, or confirmed already)"};
    PendingUpload p = std::move(it->second);
    pending.erase(it);
    return p;
  }

  Event event_from(const httplib::Request& req) {
    Event e;
    e.machine = required(req, "machine");
    e.date = required(req, "date");
    const auto kind = parse_event_kind(required(req, "kind"));
    if (!kind) throw HttpError{400, "kind: expected compensation-loaded, crash, repair or other"};
    e.kind = *kind;
    e.note = param(req, "note", 2000);
    if (!is_iso8601(e.date))
      throw HttpError{400, "date: expected an ISO 8601 date (2026-11-25), found '" + printable(e.date) + "'"};
    return e;
  }

  // ---- routes ------------------------------------------------------------------------------

  void register_routes();
};

void Server::Impl::register_routes() {
  using Req = httplib::Request;
  using Res = httplib::Response;
  const auto html = [](Res& res, std::string body) { send_uncompressed(res, std::move(body), "text/html; charset=utf-8"); };

  // Static assets: the reports' Plotly and the pages' script and style (no user data).
  add({"GET", "/static/plotly.min.js", Role::Viewer, true, false, ""}, [](const Req&, Res& res, const Context*) {
    const auto js = plotly_js();
    send_uncompressed(res, std::string(js.data(), js.size()), "application/javascript");
    // The default headers are already in res.headers: set_header would add a second Cache-Control
    // beside "no-store", which forbids storing the response whatever else is said (RFC 9111 5.2.2.5), so
    // every page with plots downloaded and compiled the 4.8 MB again.
    res.headers.erase("Cache-Control");
    res.set_header("Cache-Control", "public, max-age=86400");
  });
  add({"GET", "/static/app.js", Role::Viewer, true, false, ""}, [](const Req&, Res& res, const Context*) {
    res.set_content(app_js(), "application/javascript");
  });
  add({"GET", "/static/style.css", Role::Viewer, true, false, ""}, [](const Req&, Res& res, const Context*) {
    res.set_content(style_css(), "text/css");
  });

  add({"GET", "/login", Role::Viewer, true, false, ""}, [this, html](const Req& req, Res& res, const Context*) {
    std::string token = cookie_value(req, kLoginCookie);
    if (token.size() != 64) {
      token = random_token();
      res.set_header("Set-Cookie", std::string(kLoginCookie) + "=" + token + cookie_attributes(3600));
    }
    html(res, login_page(token, ""));
  });
  add({"POST", "/login", Role::Viewer, true, false, ""}, [this, html](const Req& req, Res& res, const Context*) {
    const std::string cookie_token = cookie_value(req, kLoginCookie);
    if (!tokens_equal(param(req, "csrf"), cookie_token))
      return send_error(res, false, 403, "the login form's CSRF token is missing or wrong: reload the login page");
    const std::string user = param(req, "user", 64), password = param(req, "password", 1024);
    const std::string addr = "addr:" + req.remote_addr;
    const long long wait = std::max(throttle.wait_seconds("user:" + user), throttle.wait_seconds(addr));
    if (wait > 0) {
      res.set_header("Retry-After", std::to_string(wait));
      return send_error(res, false, 429, fmt::format("too many failed logins: try again in {} s", wait));
    }
    auto store = pool.lease();
    const auto account = store->find_user(user);
    const bool ok = verify_password(password, account ? account->password_hash : dummy_hash) && account;
    if (!ok) {
      throttle.failure("user:" + user);
      throttle.failure(addr);
      res.status = 401;
      return html(res, login_page(cookie_token, "wrong user name or password"));
    }
    throttle.success("user:" + user);
    // A new session id at every login (no fixation: any id the browser had is not reused).
    const std::string old = cookie_value(req, kSessionCookie);
    if (old.size() == 64) store->remove_session(sha256_hex(old));
    store->remove_expired_sessions(now_utc_text());
    const std::string id = random_token();
    const auto now = std::chrono::system_clock::now();
    store->put_session({sha256_hex(id), user, random_token(), now_utc_text(now),
                        now_utc_text(now + std::chrono::hours(opt.session_hours))});
    res.status = 303;
    res.set_header("Location", "/fleet");
    res.set_header("Set-Cookie", std::string(kSessionCookie) + "=" + id + cookie_attributes(opt.session_hours * 3600));
  });
  add({"POST", "/logout", Role::Viewer, false, false, ""}, [this](const Req&, Res& res, const Context* c) {
    pool.lease()->remove_session(c->session.id_hash);
    res.status = 303;
    res.set_header("Location", "/login");
    res.set_header("Set-Cookie", std::string(kSessionCookie) + "=" + cookie_attributes(0));
  });

  add({"GET", "/", Role::Viewer, false, false, ""}, [](const Req&, Res& res, const Context*) {
    res.status = 303;
    res.set_header("Location", "/fleet");
  });
  // The fleet: its kept parts (fleet_view), gzip'd when the client accepts it (the page: the
  // user's header and the footer compressed at each request, joined to the content's kept
  // compression).
  add({"GET", "/fleet", Role::Viewer, false, false, ""}, [this, html](const Req& req, Res& res, const Context* c) {
    auto store = pool.lease();
    const bool gzip = accepts_gzip(req);
    FleetTiming timing;
    const FleetView view = fleet_view(*store, false, gzip, &timing);
    res.set_header("Server-Timing", timing.header());
    if (!gzip) return html(res, fleet_page(page_user(c), *view.html));
    const auto [before, after] = fleet_page_frame(page_user(c));
    const Deflated head = deflate_piece(before, false), tail = deflate_piece(after, true);
    res.set_header("Content-Encoding", "gzip");
    res.set_header("Vary", "Accept-Encoding");
    send_uncompressed(res, std::make_shared<const std::string>(gzip_of({&head, view.html_deflated.get(), &tail})),
                      "text/html; charset=utf-8");
  });
  add({"GET", "/api/fleet", Role::Viewer, false, true, ""}, [this](const Req& req, Res& res, const Context*) {
    auto store = pool.lease();
    const bool gzip = accepts_gzip(req);
    FleetTiming timing;
    const FleetView view = fleet_view(*store, gzip, false, &timing);
    res.set_header("Server-Timing", timing.header());
    if (!gzip) return send_uncompressed(res, view.json, "application/json");
    res.set_header("Content-Encoding", "gzip");
    res.set_header("Vary", "Accept-Encoding");
    send_uncompressed(res, view.json_gzip, "application/json");
  });
  add({"GET", "/machine", Role::Viewer, false, false, "name=M1"}, [this, html](const Req& req, Res& res, const Context* c) {
    auto store = pool.lease();
    const std::string name = required(req, "name");
    const auto [m, records] = trends(*store, name);
    html(res, machine_page(page_user(c), machine_json(*store, name, records), to_json(m)));
  });
  add({"GET", "/api/machine", Role::Viewer, false, true, "name=M1"}, [this](const Req& req, Res& res, const Context*) {
    auto store = pool.lease();
    send_json(res, machine_json(*store, required(req, "name")));
  });
  add({"GET", "/machine/trend", Role::Viewer, false, false, "name=M1"}, [this](const Req& req, Res& res, const Context*) {
    auto store = pool.lease();
    const auto [m, records] = trends(*store, required(req, "name"));
    // The report inlines Plotly and its data in <script> elements: this page alone allows inline scripts.
    res.set_header("Content-Security-Policy",
                   "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data: blob:");
    send_uncompressed(res, trend_report_html("mtcal serve", m, records, store->describe(), now_utc_text()),
                    "text/html; charset=utf-8");
  });
  add({"GET", "/api/machine/trend", Role::Viewer, false, true, "name=M1"},
      [this](const Req& req, Res& res, const Context*) {
        auto store = pool.lease();
        send_json(res, to_json(trends(*store, required(req, "name")).first));
      });
  add({"GET", "/record", Role::Viewer, false, false, "id=0"}, [this, html](const Req& req, Res& res, const Context* c) {
    auto store = pool.lease();
    const auto r = store->get(required(req, "id"));
    if (!r) throw HttpError{404, "no record '" + printable(req.get_param_value("id")) + "' in the store"};
    std::map<std::string, std::string> kinds;
    for (const auto& i : r->inputs)
      if (const auto f = store->model_file(i.sha256)) kinds[i.sha256] = f->kind;
    std::string report_missing;
    try {
      report_missing = recorded_report_missing(*store, *r);
    } catch (const InputError& e) {
      report_missing = e.what();  // a store changed by hand: the page still shows the record
    }
    html(res, record_page(page_user(c), *r, store->audit(r->id), kinds, report_missing));
  });
  // The record's own report, as its command's --report wrote it (report/recorded.hpp).
  add({"GET", "/record/report", Role::Viewer, false, false, "id=0"}, [this](const Req& req, Res& res, const Context*) {
    auto store = pool.lease();
    const auto r = store->get(required(req, "id"));
    if (!r) throw HttpError{404, "no record '" + printable(req.get_param_value("id")) + "' in the store"};
    RecordedReport rep;
    try {
      rep = recorded_report(*store, *r, Report::date_now());
    } catch (const InputError& e) {
      throw HttpError{422, e.what()};
    }
    if (rep.html.empty()) throw HttpError{404, "no report of record " + r->id + ": " + rep.why};
    // The report inlines Plotly and its data in <script> elements, as the timeline report does.
    res.set_header("Content-Security-Policy",
                   "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data: blob:");
    send_uncompressed(res, std::move(rep.html), "text/html; charset=utf-8");
  });
  add({"GET", "/api/record", Role::Viewer, false, true, "id=0"}, [this](const Req& req, Res& res, const Context*) {
    auto store = pool.lease();
    const auto r = store->get(required(req, "id"));
    if (!r) throw HttpError{404, "no record '" + printable(req.get_param_value("id")) + "' in the store"};
    send_uncompressed(res, record_to_json_line(*r) + "\n", "application/json");
  });
  add({"GET", "/diff", Role::Viewer, false, false, "a=0&b=1"}, [this, html](const Req& req, Res& res, const Context* c) {
    auto store = pool.lease();
    html(res, diff_page(page_user(c), diff_json(*store, required(req, "a"), required(req, "b"))));
  });
  add({"GET", "/api/diff", Role::Viewer, false, true, "a=0&b=1"}, [this](const Req& req, Res& res, const Context*) {
    auto store = pool.lease();
    send_json(res, diff_json(*store, required(req, "a"), required(req, "b")));
  });

  add({"GET", "/upload", Role::Engineer, false, false, ""}, [this, html](const Req& req, Res& res, const Context* c) {
    html(res, upload_page(page_user(c), param(req, "machine", 200)));
  });
  add({"POST", "/upload", Role::Engineer, false, false, ""}, [this, html](const Req& req, Res& res, const Context* c) {
    PendingUpload p = evaluate_upload(req, *c);
    const Json result = p.result;
    const CalibrationRecord rec = p.record;
    const std::string token = keep_pending(std::move(p));
    html(res, upload_preview_page(page_user(c), rec, result, token));
  });
  add({"POST", "/upload/confirm", Role::Engineer, false, false, ""},
      [this](const Req& req, Res& res, const Context* c) {
        PendingUpload p = take_pending(required(req, "token"), *c);
        const std::string machine = p.record.machine_name;
        pool.lease()->record_by(std::move(p.record), c->session.user, std::move(p.files));
        res.status = 303;
        res.set_header("Location", "/machine?name=" + url_encode(machine));
      });
  add({"POST", "/api/upload", Role::Engineer, false, true, ""}, [this](const Req& req, Res& res, const Context* c) {
    PendingUpload p = evaluate_upload(req, *c);
    Json j = p.result;
    if (param(req, "confirm") == "1")
      j["record"] = pool.lease()->record_by(std::move(p.record), c->session.user, std::move(p.files));
    send_json(res, j);
  });
  add({"POST", "/events", Role::Engineer, false, false, ""}, [this](const Req& req, Res& res, const Context* c) {
    Event e = event_from(req);
    const std::string machine = e.machine;
    pool.lease()->add_event_by(std::move(e), c->session.user);
    res.status = 303;
    res.set_header("Location", "/machine?name=" + url_encode(machine));
  });
  add({"POST", "/api/events", Role::Engineer, false, true, ""}, [this](const Req& req, Res& res, const Context* c) {
    Event e = event_from(req);
    const std::string id = pool.lease()->add_event_by(e, c->session.user);
    send_json(res, {{"id", id}, {"machine", e.machine}, {"date", e.date}, {"kind", std::string(to_string(e.kind))},
                    {"note", e.note}});
  });

  // write compensation: the files of `mtcal compensate --format F --out DIR` as DIR.zip.
  const auto send_zip = [this](const Req& req, Res& res) {
    auto [machine, out] = compensation(req);
    const std::string format = required(req, "format");
    std::string folder;
    for (const char c : machine + "-" + format)
      folder += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' ? c : '_';
    std::vector<std::pair<std::string, std::string>> files;
    for (const auto& f : out.files) files.emplace_back(folder + "/" + f.name, f.text);
    res.set_content(zip_archive(files), "application/zip");
    res.set_header("Content-Disposition", "attachment; filename=\"" + folder + ".zip\"");
  };
  add({"POST", "/machine/compensation", Role::Engineer, false, false, ""},
      [send_zip](const Req& req, Res& res, const Context*) { send_zip(req, res); });
  // The API: the zip, or with summary=1 what `compensate --json` prints (the files' names, signs,
  // residual before/after, what is not held).
  add({"POST", "/api/compensation", Role::Engineer, false, true, ""}, [this, send_zip](const Req& req, Res& res, const Context*) {
    if (param(req, "summary") != "1") return send_zip(req, res);
    auto [machine, out] = compensation(req);
    Json j = to_json(out);
    j["machine"] = machine;
    send_json(res, j);
  });

  // Calibration intervals per machine (the fleet's overdue column): admins set them.
  add({"GET", "/admin/machines", Role::Admin, false, false, ""}, [this, html](const Req&, Res& res, const Context* c) {
    auto store = pool.lease();
    html(res, machines_page(page_user(c), store->machines(), store->machine_intervals(), opt.interval_days));
  });
  const auto set_interval = [this](const Req& req, const Context* c) {
    const std::string machine = required(req, "machine");
    const auto days = number_field("days", required(req, "days"), 0, 36500);
    if (*days != std::floor(*days)) throw HttpError{400, "days: expected a whole number of days"};
    pool.lease()->set_machine_interval(machine, static_cast<int>(*days), c->session.user);
    return std::pair{machine, static_cast<int>(*days)};
  };
  add({"POST", "/admin/machines", Role::Admin, false, false, ""}, [set_interval](const Req& req, Res& res, const Context* c) {
    set_interval(req, c);
    res.status = 303;
    res.set_header("Location", "/admin/machines");
  });
  add({"GET", "/api/intervals", Role::Viewer, false, true, ""}, [this](const Req&, Res& res, const Context*) {
    Json j = Json::array();
    for (const auto& i : pool.lease()->machine_intervals())
      j.push_back({{"machine", i.machine}, {"days", i.days}, {"set_by", i.set_by}, {"set_at", i.set_at}});
    send_json(res, {{"default_days", opt.interval_days}, {"intervals", j}});
  });
  add({"POST", "/api/intervals", Role::Admin, false, true, ""}, [this, set_interval](const Req& req, Res& res, const Context* c) {
    const auto [machine, days] = set_interval(req, c);
    send_json(res, {{"machine", machine}, {"days", days == 0 ? opt.interval_days : days}, {"own", days != 0}});
  });

  add({"GET", "/admin/users", Role::Admin, false, false, ""}, [this, html](const Req&, Res& res, const Context* c) {
    html(res, users_page(page_user(c), pool.lease()->users()));
  });
  add({"GET", "/api/users", Role::Admin, false, true, ""}, [this](const Req&, Res& res, const Context*) {
    Json j = Json::array();
    for (const auto& u : pool.lease()->users())
      j.push_back({{"name", u.name}, {"role", u.role}, {"created_at", u.created_at}});
    send_json(res, {{"users", j}});
  });
  add({"POST", "/admin/users", Role::Admin, false, false, ""}, [this](const Req& req, Res& res, const Context*) {
    auto store = pool.lease();
    add_user(*store, required(req, "user"), required(req, "role"), required(req, "password"), opt.kdf_cost);
    res.status = 303;
    res.set_header("Location", "/admin/users");
  });
  // The users page's form for a plant's own tools: adds a user or changes one's role and password.
  add({"POST", "/api/users", Role::Admin, false, true, ""}, [this](const Req& req, Res& res, const Context*) {
    auto store = pool.lease();
    const std::string name = required(req, "user");
    add_user(*store, name, required(req, "role"), required(req, "password"), opt.kdf_cost);
    const auto u = store->find_user(name);
    if (!u) throw HttpError{500, "the user was not stored"};
    send_json(res, {{"name", u->name}, {"role", u->role}, {"created_at", u->created_at}});
  });
}

Server::Server(ServerOptions o) : impl_(std::make_unique<Impl>(std::move(o))) {}
Server::~Server() = default;

int Server::bind() {
  const auto& o = impl_->opt;
  const int port = o.port == 0 ? impl_->http->bind_to_any_port(o.host) : (impl_->http->bind_to_port(o.host, o.port) ? o.port : -1);
  if (port < 0) throw Error(fmt::format("cannot listen on {}:{} (in use, or not an address of this host)", o.host, o.port));
  return port;
}

// cpp-httplib's stop() only closes the listening socket once listen_after_bind() has marked the
// server running (httplib.h 0.11.4, Server::stop and Server::listen_internal): a stop() that
// comes between run()'s start and that moment did nothing, and run() then served for ever (the
// hang of server_security on a loaded machine: a test that sends no request stops the server
// at once). Here a stop() before run() makes run() return at once, and a stop() during run()'s
// start waits until httplib can be stopped.
void Server::run() {
  auto& i = *impl_;
  {
    std::lock_guard lock(i.run_mutex);
    if (i.stop_requested) return;
    i.run_state = Impl::RunState::Starting;
  }
  i.http->listen_after_bind();
  std::lock_guard lock(i.run_mutex);
  i.run_state = Impl::RunState::Returned;
  i.run_changed.notify_all();
}

void Server::stop() {
  auto& i = *impl_;
  std::unique_lock lock(i.run_mutex);
  i.stop_requested = true;
  if (i.run_state != Impl::RunState::Starting) return;  // not started (run() will not serve) or over
  // run() has begun: wait until httplib reports it running (or run() returned), then stop it.
  while (i.run_state == Impl::RunState::Starting && !i.http->is_running())
    i.run_changed.wait_for(lock, std::chrono::milliseconds(1));
  // Once only: httplib asserts that its socket is open when it stops.
  if (i.run_state == Impl::RunState::Starting && !i.http_stopped) {
    i.http_stopped = true;
    i.http->stop();
  }
}
const std::vector<Route>& Server::routes() const { return impl_->routes; }

}  // namespace mtcal::server
