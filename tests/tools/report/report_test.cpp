// spinewatch report: the HTML report and CSV from summary lines, rendered
// in headless Chromium (Debian's chromium), its figures read back from the
// DOM and checked against the summaries they were made from.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <regex>

#include <nlohmann/json.hpp>

#include "spinewatch/estimator/load/exposure_accumulator.hpp"
#include "spinewatch/estimator/load/exposure_json.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

constexpr std::int64_t kSecond = 1'000'000'000;
// 2026-12-02T08:00:00Z, on the stream's clock at 1000 s.
constexpr std::int64_t kUtcOffset = 1'796'198'400LL * kSecond - 1000 * kSecond;

Posture posture_at(std::int64_t t_ns, double inclination, double lateral, double l5_n) {
  Posture p;
  p.t_ns = t_ns;
  p.state = TrackingState::Tracking;
  Ergonomics e;
  e.trunk_inclination_deg = inclination;
  e.lateral_bend_deg = lateral;
  e.reba_trunk = reba_trunk_score({inclination, lateral, 0}, default_ergonomic_limits());
  p.ergonomics = e;
  p.loads = {{"L5", l5_n}};
  return p;
}

// 24 minutes at 10 postures a second: the first 12 with long stoops, the
// last 12 mostly upright (a bench raised at minute 12), a lost stretch in
// minute 5; worker w-17, then w-20 for the last 4 minutes.
std::filesystem::path write_summaries(const test::TempDir& dir) {
  ExposureOptions o;
  o.align_ns = kUtcOffset;
  ExposureAccumulator acc(o);
  const auto path = dir / "shift.ndjson";
  std::ofstream out(path);
  out << "{\"class\":\"hello\",\"v\":1}\n";  // other classes are skipped
  SummaryLabels labels{.station = "bench 3", .worker = "w-17", .utc_offset_ns = kUtcOffset};
  auto emit = [&](const std::vector<ExposureSummary>& closed) {
    for (const auto& s : closed) out << encode_summary(s, labels) << '\n';
  };
  for (std::int64_t i = 0; i < 24 * 600; ++i) {
    const std::int64_t t = 1000 * kSecond + i * kSecond / 10;
    const int minute = int(i / 600), second = int(i / 10 % 60);
    const bool before = minute < 12;
    double inclination = second < 20 ? 5 : second < 40 ? (before ? 45 : 15) : (before && second >= 55 ? 70 : 10);
    if (second == 30 && minute % 3 == 0) inclination = -8;
    const double lateral = second % 15 < 2 ? 14 : 0;
    Posture p = posture_at(t, inclination, lateral, 800 + 40 * inclination);
    if (minute == 5 && second < 30) {
      p.state = TrackingState::Lost;
      p.ergonomics.reset();
    }
    emit(acc.add(p));  // closes the previous minute: labelled before the worker changes
    if (minute == 20) labels.worker = "w-20";
  }
  emit(acc.finish());
  return path;
}

std::vector<nlohmann::json> intervals_of(const std::filesystem::path& path, const std::string& worker) {
  std::vector<nlohmann::json> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    auto j = nlohmann::json::parse(line);
    if (j.value("class", "") == "summary" && j.at("scope") == "interval" && j.value("worker", "") == worker)
      out.push_back(j);
  }
  return out;
}

// Every element of the DOM with class="cls": its attributes.
std::vector<std::map<std::string, std::string>> elements(const std::string& dom, const std::string& cls) {
  std::vector<std::map<std::string, std::string>> out;
  const std::regex tag("<[a-z]+ [^>]*class=\"" + cls + "\"[^>]*>"), attr("([a-z-]+)=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(dom.begin(), dom.end(), tag); it != std::sregex_iterator(); ++it) {
    const std::string t = it->str();
    std::map<std::string, std::string> a;
    for (auto m = std::sregex_iterator(t.begin(), t.end(), attr); m != std::sregex_iterator(); ++m) a[(*m)[1]] = (*m)[2];
    out.push_back(a);
  }
  return out;
}
double num(const std::map<std::string, std::string>& a, const std::string& key) { return std::stod(a.at(key)); }

std::string chromium(const test::TempDir& dir, const std::string& args) {
  return "timeout 90 chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
         "--disable-background-networking --disable-component-update --disable-sync --user-data-dir='" +
         (dir / "chromium-profile").string() + "' " + args + " 2>/dev/null";
}

TEST(Report, HtmlAndCsvFromSummariesCheckedInHeadlessChromium) {
  test::TempDir dir;
  const auto summaries = write_summaries(dir);
  const auto expected = intervals_of(summaries, "w-17");
  ASSERT_EQ(expected.size(), 20u);
  const auto out = dir / "report";
  auto r = test::run_cli("report --summaries " + summaries.string() + " --worker w-17 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;

  // CSV: a header and one row per interval of the worker.
  const std::string csv = test::read_file(out / "summaries.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 21);
  EXPECT_EQ(csv.substr(0, csv.find(',')), "utc_start");
  EXPECT_NE(csv.find("\n2026-12-02T08:00:00.000Z,2026-12-02T08:01:00.000Z,"), std::string::npos) << csv.substr(0, 600);

  // Self-contained: nothing fetched from anywhere.
  const std::string html = test::read_file(out / "report.html");
  for (const char* external : {"<script", "<link", "src=", "url(", "@import"})
    EXPECT_EQ(html.find(external), std::string::npos) << external;
  EXPECT_EQ(std::regex_search(html, std::regex("https?://(?!www\\.w3\\.org/2000/svg)")), false);

  if (test::run_command("command -v chromium").exit_code != 0)
    GTEST_SKIP() << "chromium is not installed (scripts/install-deps installs it)";
  auto dump = test::run_command(chromium(dir, "--dump-dom 'file://" + (out / "report.html").string() + "'"));
  if (dump.exit_code != 0 || dump.output.find("<svg") == std::string::npos)
    GTEST_SKIP() << "chromium cannot run here (exit " << dump.exit_code << "): " << dump.output.substr(0, 300);
  const std::string& dom = dump.output;

  // Time in zone: each bar's figure is the sum over the intervals, and its
  // length is in proportion.
  std::map<std::string, double> zone_sum;
  double tracked = 0;
  for (const auto& j : expected) {
    tracked += j.at("coverage").at("tracked_s").get<double>();
    for (auto& [k, v] : j.at("trunk_inclination").at("zones_s").items()) zone_sum[k] += v.get<double>();
  }
  const auto bars = elements(dom, "zone-bar");
  ASSERT_EQ(bars.size(), 4u);
  double longest = 0;
  for (const auto& b : bars) longest = std::max(longest, zone_sum.at(b.at("data-zone")));
  const double full = [&] {
    for (const auto& b : bars)
      if (zone_sum.at(b.at("data-zone")) == longest) return num(b, "width");
    return 0.0;
  }();
  for (const auto& b : bars) {
    const double s = zone_sum.at(b.at("data-zone"));
    EXPECT_NEAR(num(b, "data-seconds"), s, 1e-3) << b.at("data-zone");
    EXPECT_NEAR(num(b, "width"), full * s / longest, 0.02) << b.at("data-zone");
  }
  EXPECT_GT(zone_sum.at("over_60"), 0);
  EXPECT_GT(zone_sum.at("extension"), 0);

  // Inclination over time: one dot per interval with anything tracked, at
  // its mean; lower on the page for a lower angle.
  const auto dots = elements(dom, "incl-mean");
  ASSERT_EQ(dots.size(), expected.size());
  for (std::size_t i = 0; i < dots.size(); ++i) {
    EXPECT_EQ(dots[i].at("data-start-ns"), std::to_string(expected[i].at("start_ns").get<std::int64_t>()));
    EXPECT_NEAR(num(dots[i], "data-deg"), expected[i].at("trunk_inclination").at("mean_deg").get<double>(), 0.006);
  }
  for (std::size_t i = 1; i < dots.size(); ++i) {
    if (num(dots[i], "data-deg") < num(dots[i - 1], "data-deg") - 0.1) {
      EXPECT_GT(num(dots[i], "cy"), num(dots[i - 1], "cy"));
    }
  }

  // Load over time: peaks per interval and the action limit.
  const auto peaks = elements(dom, "load-peak");
  ASSERT_EQ(peaks.size(), expected.size());
  for (std::size_t i = 0; i < peaks.size(); ++i)
    EXPECT_NEAR(num(peaks[i], "data-n"), expected[i].at("lumbar_compression").at("peak_n").get<double>(), 0.06);
  ASSERT_EQ(elements(dom, "action-limit").size(), 1u);
  EXPECT_EQ(elements(dom, "action-limit")[0].at("data-n"), "3400");

  // REBA strip: one cell per interval with its distribution.
  const auto cells = elements(dom, "reba-cell");
  ASSERT_EQ(cells.size(), expected.size());
  for (std::size_t i = 0; i < cells.size(); ++i) {
    double weighted = 0, total = 0;
    for (std::size_t k = 0; k < 5; ++k) {
      const double s = expected[i].at("reba_trunk_s")[k].get<double>();
      weighted += double(k + 1) * s;
      total += s;
    }
    EXPECT_NEAR(num(cells[i], "data-mean"), weighted / total, 1e-3);
  }

  // Comparison: halves of the 20 intervals. The first (minutes 0–9) stoops
  // every minute; the second only in minutes 10 and 11 (the bench raised
  // at minute 12): less time beyond 60°, and less at 20–60°.
  const auto cmp = elements(dom, "cmp-bar");
  ASSERT_EQ(cmp.size(), 8u);
  std::map<std::string, double> pct;
  for (const auto& c : cmp) pct[c.at("data-period") + c.at("data-zone")] = num(c, "data-percent");
  double a_tracked = 0, a_flexed = 0;
  for (std::size_t i = 0; i < 10; ++i) {
    a_tracked += expected[i].at("coverage").at("tracked_s").get<double>();
    a_flexed += expected[i].at("trunk_inclination").at("zones_s").at("20_60").get<double>();
  }
  EXPECT_NEAR(pct.at("a20_60"), 100 * a_flexed / a_tracked, 1e-2);
  EXPECT_GT(pct.at("a20_60"), pct.at("b20_60"));
  EXPECT_GT(pct.at("aover_60"), 4 * pct.at("bover_60"));
  EXPECT_GT(pct.at("bover_60"), 0);
  const auto meta = elements(dom, "meta");
  ASSERT_FALSE(meta.empty());
  EXPECT_NEAR(num(meta[0], "data-tracked-s"), tracked, 1e-3);

  // A picture of it: the PNG a person would look at.
  const auto png = dir / "report.png";
  auto shot = test::run_command(chromium(dir, "--window-size=860,2400 --hide-scrollbars --screenshot='" + png.string() +
                                                  "' 'file://" + (out / "report.html").string() + "'"));
  ASSERT_EQ(shot.exit_code, 0) << shot.output;
  const std::string bytes = test::read_file(png);
  ASSERT_GT(bytes.size(), 20'000u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
}

// The report `make demo` writes (scripts/demo-report, the demo's step 1 run
// as the demo runs it): it renders in headless Chromium, with one inclination
// dot and one load peak per tracked interval of its summaries, at the
// summaries' figures, and one REBA cell per interval.
TEST(Report, TheDemosReportRendersInHeadlessChromium) {
  test::TempDir dir;
  const auto work = dir / "demo";
  auto r = test::run_command("cd '" + test::source_path("").string() + "' && scripts/demo-report " + test::cli_path() +
                             " '" + work.string() + "' 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::vector<nlohmann::json> intervals, tracked;  // every interval; those with postures tracked
  for (const auto& j : test::read_ndjson(work / "summaries.ndjson")) {
    if (j.value("class", "") != "summary" || j.at("scope") != "interval") continue;
    intervals.push_back(j);
    if (j.at("coverage").at("tracked_s").get<double>() > 0 &&
        j.at("lumbar_compression").at("based_on_s").get<double>() > 0)
      tracked.push_back(j);
  }
  ASSERT_GE(tracked.size(), 2u) << "the demo's 3-second flexion gives one summary a second";

  if (test::run_command("command -v chromium").exit_code != 0)
    GTEST_SKIP() << "chromium is not installed (scripts/install-deps installs it)";
  auto dump = test::run_command(chromium(dir, "--dump-dom 'file://" + (work / "report" / "report.html").string() + "'"));
  if (dump.exit_code != 0 || dump.output.find("<svg") == std::string::npos)
    GTEST_SKIP() << "chromium cannot run here (exit " << dump.exit_code << "): " << dump.output.substr(0, 300);
  const std::string& dom = dump.output;
  const auto dots = elements(dom, "incl-mean");
  const auto peaks = elements(dom, "load-peak");
  ASSERT_EQ(dots.size(), tracked.size());
  ASSERT_EQ(peaks.size(), tracked.size());
  EXPECT_EQ(elements(dom, "reba-cell").size(), intervals.size());
  for (std::size_t i = 0; i < tracked.size(); ++i) {
    EXPECT_NEAR(num(dots[i], "data-deg"), tracked[i].at("trunk_inclination").at("mean_deg").get<double>(), 0.006);
    EXPECT_NEAR(num(peaks[i], "data-n"), tracked[i].at("lumbar_compression").at("peak_n").get<double>(), 0.06);
  }
  EXPECT_EQ(elements(dom, "zone-bar").size(), 4u);
}

TEST(Report, TimeRangesPeriodsAndBadInput) {
  test::TempDir dir;
  const auto summaries = write_summaries(dir);
  const auto out = dir / "r";
  // Minutes 2–5 of the shift: four intervals.
  auto r = test::run_cli("report --summaries " + summaries.string() +
                         " --from 2026-12-02T08:02:00Z --to 2026-12-02T08:06:00Z --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string rows = test::read_file(out / "summaries.csv");
  EXPECT_EQ(std::count(rows.begin(), rows.end(), '\n'), 5);
  // Seconds of the stream select the same.
  auto s = test::run_cli("report --summaries " + summaries.string() + " --from 1120 --to 1360 --out " + (dir / "s").string());
  ASSERT_EQ(s.exit_code, 0) << s.output;
  EXPECT_EQ(test::read_file(dir / "s" / "summaries.csv"), test::read_file(out / "summaries.csv"));
  // Named periods for the comparison: their text is the legend.
  auto p = test::run_cli("report --summaries " + summaries.string() +
                         " --period-a 2026-12-02T08:00:00Z/2026-12-02T08:12:00Z --period-b "
                         "2026-12-02T08:12:00Z/2026-12-02T08:24:00Z --out " + (dir / "p").string());
  ASSERT_EQ(p.exit_code, 0) << p.output;
  EXPECT_NE(test::read_file(dir / "p" / "report.html").find("A: 2026-12-02T08:00:00Z/2026-12-02T08:12:00Z"),
            std::string::npos);

  auto none = test::run_cli("report --out " + out.string());
  EXPECT_EQ(none.exit_code, 2) << none.output;
  auto bad_time = test::run_cli("report --summaries " + summaries.string() + " --from yesterday --out " + out.string());
  EXPECT_EQ(bad_time.exit_code, 2);
  EXPECT_NE(bad_time.output.find("--from \"yesterday\": not a time"), std::string::npos) << bad_time.output;
  auto lonely = test::run_cli("report --summaries " + summaries.string() + " --period-a 0/10 --out " + out.string());
  EXPECT_EQ(lonely.exit_code, 2);
  auto empty = test::run_cli("report --summaries " + summaries.string() + " --worker nobody --out " + out.string());
  EXPECT_EQ(empty.exit_code, 1);
  EXPECT_NE(empty.output.find("nothing to report"), std::string::npos) << empty.output;
  test::write_file(dir / "broken.ndjson", "{\"class\":\"summary\",\"v\":1,\"scope\":\"interval\",\"start_ns\":0}\n");
  auto broken = test::run_cli("report --summaries " + (dir / "broken.ndjson").string() + " --out " + out.string());
  EXPECT_EQ(broken.exit_code, 1);
  EXPECT_NE(broken.output.find("broken.ndjson:1: end_ns: expected an integer"), std::string::npos) << broken.output;
}

}  // namespace
}  // namespace spinewatch
