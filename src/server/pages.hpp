// The HTML pages of mtcal serve: server-rendered, every value escaped, no inline script.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mtcal/history/record.hpp"
#include "mtcal/io/history/store.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal::server {

// Who looks at a page (empty name: nobody logged in) and the session's CSRF token for its forms.
struct PageUser {
  std::string name, role, csrf;
  bool engineer = false, admin = false;
};

// Percent-encoding of a query parameter's value (RFC 3986 unreserved characters kept).
std::string url_encode(const std::string& s);

std::string error_page(int status, const std::string& message);
std::string login_page(const std::string& csrf, const std::string& error);
// The fleet page in three parts, so that the server keeps the parts that are the same for
// every user between requests: one machine's rows of the table (machine: an entry of
// /api/fleet's "machines"), the page's content around the rows of every machine (fleet:
// /api/fleet's other keys), and the page of a user around that content.
std::string fleet_machine_rows(const Json& machine, bool ranked);
std::string fleet_page_body(const Json& fleet, std::size_t machines, std::size_t overdue, std::string_view rows);
std::string fleet_page(const PageUser& u, const std::string& body);
// fleet_page's text before and after the content (a page compressed in parts: the content's kept).
std::pair<std::string, std::string> fleet_page_frame(const PageUser& u);
// machine: what /api/machine returns; trends: what /api/machine/trend returns.
std::string machine_page(const PageUser& u, const Json& machine, const Json& trends);
// model_kinds: per SHA-256 of the record's inputs that the store holds as a model file, its kind
// ("machine", "parameters").
// report_missing: why the record's own report cannot be made (recorded_report_missing), empty
// when /record/report shows it.
std::string record_page(const PageUser& u, const CalibrationRecord& r, const std::vector<AuditEntry>& audit,
                        const std::map<std::string, std::string>& model_kinds, const std::string& report_missing);
// diff: what /api/diff returns (history diff --json).
std::string diff_page(const PageUser& u, const Json& diff);
std::string upload_page(const PageUser& u, const std::string& machine);
std::string upload_preview_page(const PageUser& u, const CalibrationRecord& r, const Json& result,
                                const std::string& token);
std::string users_page(const PageUser& u, const std::vector<UserAccount>& users);
// Calibration intervals: every machine of the store, its own interval or the default, a form.
std::string machines_page(const PageUser& u, const std::vector<std::string>& machines,
                          const std::vector<MachineInterval>& intervals, int default_days);

// The pages' script (table sorting and filtering, plots from JSON data elements) and style.
const std::string& app_js();
const std::string& style_css();

}  // namespace mtcal::server
