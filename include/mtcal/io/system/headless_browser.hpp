// Headless Chromium renders a report page where JavaScript cannot run: to PDF, and its plot images.
#pragma once

#include <string>

namespace mtcal {

struct HeadlessBrowser {
  std::string program;     // the browser's executable
  double timeout_s = 120;  // per rendering, wall clock
};

// $MTCAL_CHROMIUM when it is set, else the first of chromium, chromium-browser, google-chrome,
// google-chrome-stable on PATH. Throws Error naming what was looked for and the Debian package
// when none is installed.
HeadlessBrowser find_headless_browser(double timeout_s = 120);

// The page (HTML text) opened from a private temporary directory (removed afterwards), its
// scripts run (the browser's virtual time, 30 s of it, so that the plots and their print images
// are made), then printed with the page's print stylesheet, no header or footer: the PDF's bytes.
// Throws Error with the browser's last message when it fails, times out or writes no PDF.
std::string print_to_pdf(const HeadlessBrowser& browser, const std::string& html);

// The same page's DOM after its scripts ran (Chromium's --dump-dom), as HTML text.
std::string rendered_dom(const HeadlessBrowser& browser, const std::string& html);

}  // namespace mtcal
