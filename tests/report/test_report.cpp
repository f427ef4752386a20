// The report module: SHA-256 against FIPS 180-4 examples, escaping, and the document's parts.
#include <gtest/gtest.h>

#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"

using namespace mtcal;

TEST(Report, Sha256MatchesFips180Examples) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(std::string(1000000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Report, EscapesTextAndScripts) {
  EXPECT_EQ(html_escape("<a href=\"x\">&'"), "&lt;a href=&quot;x&quot;&gt;&amp;&#39;");
  const std::string js = script_safe_json({{"name", "</script><!--"}});
  EXPECT_EQ(js.find("</"), std::string::npos);
  EXPECT_EQ(js.find("<!--"), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(js)["name"], "</script><!--");  // still the same JSON value
}

TEST(Report, DocumentHasSummaryFiguresWarningsTablesAndPlots) {
  Report r("Title <1>", "mtcal eval --x");
  r.add_figure("largest error", "12.5", "µm");
  r.add_warning("check <this>");
  r.add_section("Section");
  r.add_table("caption", {"a", "b"}, {{"1", "<2>"}});
  r.add_plot("plot",
             {{"data", {{{"type", "bar"}, {"x", {1, 2}}, {"y", {3, 4}}}}}, {"layout", nlohmann::json::object()}});
  EXPECT_EQ(r.plot_count(), 1u);
  const std::string h = r.html("2026-01-01 00:00:00 UTC");
  for (const char* part :
       {"<title>Title &lt;1&gt; - mtcal</title>", "<code>mtcal eval --x</code>",
        "<td class=\"date\">2026-01-01 00:00:00 UTC</td>", "<td class=\"value\">12.5</td><td>µm</td>",
        "<li>check &lt;this&gt;</li>", "<h2>Section</h2>", "<td>&lt;2&gt;</td>", "Plotly.newPlot('plot-1'"})
    EXPECT_NE(h.find(part), std::string::npos) << part;
  EXPECT_NE(h.find(std::string(plotly_js())), std::string::npos);  // the library is inlined
  EXPECT_GT(plotly_js().size(), 1000000u);
  // Deterministic: a second report built the same way gives the same bytes.
  Report again("Title <1>", "mtcal eval --x");
  again.add_figure("largest error", "12.5", "µm");
  again.add_warning("check <this>");
  again.add_section("Section");
  again.add_table("caption", {"a", "b"}, {{"1", "<2>"}});
  again.add_plot("plot",
                 {{"data", {{{"type", "bar"}, {"x", {1, 2}}, {"y", {3, 4}}}}}, {"layout", nlohmann::json::object()}});
  EXPECT_EQ(again.html("2026-01-01 00:00:00 UTC"), h);
  EXPECT_THROW(r.add_input("data", "/nonexistent/file.csv"), InputError);
  // The <noscript> note on static copies: the library's words by default (no option of a
  // command), the writing program's own where it sets one.
  const std::size_t note = h.find("<noscript><div class=\"warnings noscript\">");
  ASSERT_NE(note, std::string::npos);
  const std::string noscript = h.substr(note, h.find("</noscript>", note) - note);
  EXPECT_NE(noscript.find("A static copy for e-mail"), std::string::npos) << noscript;
  EXPECT_EQ(noscript.find("--"), std::string::npos) << noscript;
  const std::string before = static_copy_note();
  set_static_copy_note("print it with <code>write_report(pdf=...)</code>");
  const std::string named = r.html("2026-01-01 00:00:00 UTC");
  set_static_copy_note(before);
  EXPECT_NE(named.find("print it with <code>write_report(pdf=...)</code></div></noscript>"), std::string::npos);
}
