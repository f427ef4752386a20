// Starting another program (io/system/process.hpp) and reading a rendered report's plot images
// (report/report.hpp): exit status, output, signals, the time limit, no shell, bad input.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <string>

#include "mtcal/io/system/process.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"

using namespace mtcal;

TEST(Process, KeepsOutputAndExitStatusWithoutAShell) {
  const auto sh = find_program({"sh"});
  ASSERT_TRUE(sh);
  // One argument with shell syntax in it reaches the program as it is.
  const ProgramRun r =
      run_program({*sh, "-c", "printf '%s|' \"$0\" \"$1\"; echo oops >&2; exit 4", "a b", "$(x); y"}, 10);
  EXPECT_EQ(r.out, "a b|$(x); y|");
  EXPECT_EQ(r.err, "oops\n");
  EXPECT_EQ(r.exit_status, 4);
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(run_program({*sh, "-c", "exit 0"}, 10).ok());
  const ProgramRun killed = run_program({*sh, "-c", "kill -TERM $$"}, 10);
  EXPECT_EQ(killed.signal, SIGTERM);
  EXPECT_EQ(killed.exit_status, -1);
}

// NAME=value entries replace the inherited variable or add one; the rest is inherited; a malformed entry is refused.
TEST(Process, EnvironmentEntriesReplaceOrAdd) {
  const auto sh = find_program({"sh"});
  ASSERT_TRUE(sh);
  ::setenv("MTCAL_TEST_KEPT", "kept", 1);
  ::setenv("MTCAL_TEST_REPLACED", "old", 1);
  const ProgramRun r = run_program(
      {*sh, "-c", "printf '%s|%s|%s|%s' \"$MTCAL_TEST_KEPT\" \"$MTCAL_TEST_REPLACED\" \"$MTCAL_TEST_NEW\" "
                  "\"$(env | grep -c '^MTCAL_TEST_REPLACED=')\""},
      10, std::size_t{1} << 20, {}, {"MTCAL_TEST_REPLACED=new=1", "MTCAL_TEST_NEW="});
  EXPECT_EQ(r.out, "kept|new=1||1");
  EXPECT_EQ(run_program({*sh, "-c", "printf %s \"$MTCAL_TEST_REPLACED\""}, 10).out, "old");
  for (const std::string bad : {"NOEQUALS", "=value", ""}) {
    try {
      run_program({*sh, "-c", "exit 0"}, 10, std::size_t{1} << 20, {}, {bad});
      ADD_FAILURE() << "no error for '" << bad << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("is not NAME=value"), std::string::npos) << e.what();
    }
  }
  ::unsetenv("MTCAL_TEST_KEPT");
  ::unsetenv("MTCAL_TEST_REPLACED");
}

TEST(Process, TimeLimitKillsTheProgramAndItsHelpers) {
  const auto sh = find_program({"sh"});
  ASSERT_TRUE(sh);
  const auto start = std::chrono::steady_clock::now();
  // A helper in the background holds the pipes open: the group is killed, not waited for.
  const ProgramRun r = run_program({*sh, "-c", "sleep 30 & echo started; sleep 30"}, 0.5);
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(r.timed_out);
  EXPECT_EQ(r.signal, SIGKILL);
  EXPECT_EQ(r.out, "started\n");
  EXPECT_LT(took, 5.0);
  // The program exits while a helper still holds its output open: not waited for either.
  const auto start2 = std::chrono::steady_clock::now();
  const ProgramRun r2 = run_program({*sh, "-c", "sleep 30 & echo done"}, 20);
  EXPECT_TRUE(r2.ok());
  EXPECT_EQ(r2.out, "done\n");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start2).count(), 5.0);
}

TEST(Process, MissingProgramIsAnError) {
  EXPECT_FALSE(find_program({"mtcal-no-such-program", "/nonexistent/x"}));
  EXPECT_TRUE(find_program({"mtcal-no-such-program", "sh"}));
  try {
    run_program({"/nonexistent/chromium", "--headless"}, 5);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot start /nonexistent/chromium"), std::string::npos) << e.what();
  }
}

TEST(Process, PlotImagesFromARenderedPage) {
  // A 1x1 PNG (RFC 4648 base64 of its bytes, which start with the PNG signature).
  const std::string png64 =
      "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8DwHwAFBQIAX8jx0gAAAABJRU5ErkJggg==";
  const std::string img = "<img class=\"plot-print\" alt=\"a\" src=\"data:image/png;base64," + png64 + "\">";
  const auto images = plot_images_from_dom("<html><body><div class=\"plot\"></div>" + img + "<p>x</p>" + img);
  ASSERT_EQ(images.size(), 2u);
  EXPECT_EQ(images[0].size(), 70u);  // 96 base64 characters, 2 of them padding: 96 / 4 * 3 - 2
  EXPECT_EQ(images[0].substr(0, 8), "\x89PNG\r\n\x1a\n");
  EXPECT_EQ(images[0].substr(images[0].size() - 8, 4), "IEND");
  EXPECT_TRUE(plot_images_from_dom("<html><img src=\"data:image/png;base64,AAAA\"></html>").empty());  // not ours
  EXPECT_THROW(plot_images_from_dom("<img class=\"plot-print\" src=\"data:image/jpeg;base64,AAAA\">"), Error);
  EXPECT_THROW(plot_images_from_dom("<img class=\"plot-print\" src=\"data:image/png;base64,AA*A\">"), Error);
  EXPECT_THROW(plot_images_from_dom("<img class=\"plot-print\" src=\"data:image/png;base64,QUJD\">"), Error);  // "ABC"
  EXPECT_EQ(plot_image_paths("out/x.html", "dir", 2),
            (std::vector<std::string>{"dir/x-plot-1.png", "dir/x-plot-2.png"}));
}
