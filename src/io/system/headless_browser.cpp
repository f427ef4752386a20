// Headless Chromium renderings of a page (io/system/headless_browser.hpp). The switches are Chromium's
// command-line switches (peter.sh/experiments/chromium-command-line-switches, and `chromium
// --help` of Debian's package): --headless, --print-to-pdf=FILE, --dump-dom, --virtual-time-budget.
#include "mtcal/io/system/headless_browser.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>

#include <fmt/format.h>

#include "mtcal/io/system/files.hpp"
#include "mtcal/io/system/process.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

// A private directory for the page and the browser's profile, removed with everything in it.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "mtcal-browser-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw Error("cannot make a temporary directory for the browser in " + pattern);
    path = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

// The last non-empty line of the browser's messages, for an error.
std::string last_line(const std::string& text) {
  std::size_t end = text.find_last_not_of("\r\n \t");
  if (end == std::string::npos) return "no message";
  const std::size_t start = text.rfind('\n', end);
  std::string line =
      text.substr(start == std::string::npos ? 0 : start + 1, end - (start == std::string::npos ? 0 : start + 1) + 1);
  if (line.size() > 300) line = line.substr(0, 300) + "...";
  return line;
}

// Runs the browser on the page with what (the switches of one rendering); returns its run.
ProgramRun render(const HeadlessBrowser& b, const TempDir& dir, const std::string& html,
                  const std::vector<std::string>& what, const std::string& purpose) {
  const auto page = dir.path / "report.html";
  {
    // Written now, not through the command's output group: the browser reads it before the end.
    std::ofstream out(page, std::ios::binary);
    out << html;
    out.close();
    if (!out) throw Error("cannot write the page for the browser to " + page.string());
  }
  std::vector<std::string> argv = {b.program, "--headless",
                                   // Root in a container has no user namespace for the sandbox;
                                   // the page is mtcal's own report, read from a private directory.
                                   "--no-sandbox", "--disable-gpu",
                                   "--enable-unsafe-swiftshader",  // software WebGL for the 3D plots
                                   "--disable-dev-shm-usage", "--no-first-run", "--no-default-browser-check",
                                   "--disable-background-networking", "--disable-component-update", "--disable-sync",
                                   "--disable-breakpad", "--disable-extensions", "--hide-scrollbars",
                                   "--window-size=1280,800", "--user-data-dir=" + (dir.path / "profile").string(),
                                   "--virtual-time-budget=30000", "--run-all-compositor-stages-before-draw"};
  argv.insert(argv.end(), what.begin(), what.end());
  argv.push_back("file://" + page.string());
  ProgramRun run = run_program(argv, b.timeout_s);
  if (run.timed_out) throw Error(fmt::format("{} ({}) did not finish in {:g} s", purpose, b.program, b.timeout_s));
  if (!run.ok())
    throw Error(fmt::format("{} ({}) failed ({}): {}", purpose, b.program,
                            run.signal ? fmt::format("signal {}", run.signal) : fmt::format("exit {}", run.exit_status),
                            last_line(run.err)));
  return run;
}

}  // namespace

HeadlessBrowser find_headless_browser(double timeout_s) {
  HeadlessBrowser b;
  b.timeout_s = timeout_s;
  if (const char* env = std::getenv("MTCAL_CHROMIUM"); env && *env) {
    const auto p = find_program({env});
    if (!p) throw Error(fmt::format("MTCAL_CHROMIUM names '{}', which is not an executable program", env));
    b.program = *p;
    return b;
  }
  const auto p = find_program({"chromium", "chromium-browser", "google-chrome", "google-chrome-stable"});
  if (!p)
    throw Error(
        "a static copy of the report (PDF, PNG) is made by headless Chromium, which is not installed: no chromium, "
        "chromium-browser, google-chrome or google-chrome-stable on PATH (Debian: apt-get install chromium; or set "
        "MTCAL_CHROMIUM to its path)");
  b.program = *p;
  return b;
}

std::string print_to_pdf(const HeadlessBrowser& b, const std::string& html) {
  TempDir dir;
  const auto pdf = dir.path / "report.pdf";
  // --no-pdf-header-footer is the switch of Chromium >= 111, --print-to-pdf-no-header the older one.
  render(b, dir, html, {"--no-pdf-header-footer", "--print-to-pdf-no-header", "--print-to-pdf=" + pdf.string()},
         "printing the report to PDF");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(pdf, ec))
    throw Error(fmt::format("printing the report to PDF ({}) wrote no PDF", b.program));
  std::string bytes = read_text_file(pdf.string(), "PDF");
  if (bytes.rfind("%PDF-", 0) != 0)
    throw Error(fmt::format("printing the report to PDF ({}) wrote a file that is not a PDF", b.program));
  return bytes;
}

std::string rendered_dom(const HeadlessBrowser& b, const std::string& html) {
  TempDir dir;
  ProgramRun run = render(b, dir, html, {"--dump-dom"}, "rendering the report");
  if (run.out.find("<html") == std::string::npos)
    throw Error(fmt::format("rendering the report ({}) gave no page: {}", b.program, last_line(run.err)));
  return std::move(run.out);
}

}  // namespace mtcal
