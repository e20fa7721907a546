// The live view page in a real browser: headless Chromium (Debian's
// chromium) loads / from the real daemon started as `make demo` starts it
// (config/demo.toml: the embedded default, the live view on loopback), twice a
// second apart; the page's spine side view (an SVG polyline the page
// draws from /state) must show a tracked spine both times, and a different
// one as the phantom bends, and the page's MJPEG <img> must have received
// frames (the daemon counts the parts it wrote). A screenshot of the page is left in the build
// tree (live_view.png; docs/images/live-view.png is one). Where Chromium
// is missing or cannot start, the test says so and is skipped.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <regex>

#include <opencv2/imgcodecs.hpp>

#include "test_support.hpp"
#include "http_daemon.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;

const char* kChromium = "/usr/bin/chromium";

std::string chromium(const test::TempDir& dir, const std::string& what, const std::string& url) {
  static int profile = 0;
  const auto user_data = dir / ("profile" + std::to_string(profile++));
  return std::string("timeout 90 ") + kChromium +
         " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking"
         " --disable-component-update --disable-sync --user-data-dir='" +
         user_data.string() + "' --virtual-time-budget=4000 " + what + " '" + url + "'";
}

std::string attribute(const std::string& dom, const std::string& id, const std::string& name) {
  std::smatch m;
  if (std::regex_search(dom, m, std::regex("id=\"" + id + "\"[^>]*" + name + "=\"([^\"]*)\""))) return m[1];
  return "";
}

TEST(LiveViewBrowser, TheSpineViewFollowsThePhantomAndAScreenshotIsTaken) {
  if (!std::filesystem::exists(kChromium)) GTEST_SKIP() << kChromium << " is not installed (scripts/install-deps installs chromium)";
  test::TempDir dir;
  // Started as `make demo` starts it (config/demo.toml), so that what is
  // checked here is what the demo shows.
  test::HttpDaemon daemon(dir, test::HttpDaemon::AsTheDemo{});
  ASSERT_TRUE(daemon.wait_for_state("tracking", test::scaled(20s))) << daemon.process().log();
  const std::string url = "http://127.0.0.1:" + std::to_string(daemon.http_port()) + "/";
  const auto frames_written = [&] {
    const auto m = test::http_get(daemon.http_port(), "/metrics").body;
    const std::string name = "\nspinewatch_http_stream_frames_total ";
    const auto at = m.find(name);
    return at == std::string::npos ? -1L : std::stol(m.substr(at + name.size()));
  };
  const long frames_before = frames_written();
  ASSERT_GE(frames_before, 0);

  // Pages a second or more apart that show a tracked spine, until two
  // show different spines. The embedded default loops a recording whose
  // first frames are the empty scene: a page loaded then rightly shows
  // "lost" and is taken again. Once (the sanitizer build in a CI run) two pages 1.2 s apart showed the same spine to the last digit;
  // why is not known (no two successive postures of that recording are
  // equal), so a page is taken again then too. A view that stopped
  // following the phantom shows one spine on all ten loads, and fails.
  std::vector<std::string> spines;
  std::vector<std::string> other_states;
  const auto two_differ = [&] { return spines.size() >= 2 && spines.front() != spines.back(); };
  // The pauses between loads differ by 1.1 s from one to the next: with a
  // fixed pause, a load plus its pause can come close to the recording's
  // loop (130 frames, 4.3 s), and then every page lands on the same part
  // of it — under the sanitizers on a busy 2-core machine, four pages in a
  // row on its empty frames ("lost", 8 % of the loop).
  for (int load = 0; load < 10 && !two_differ(); ++load) {
    if (load > 0) std::this_thread::sleep_for(1200ms + (load % 4) * 1100ms);
    const auto r = test::run_command(chromium(dir, "--dump-dom", url) + " 2>" + (dir / "chromium.err").string());
    if (r.exit_code != 0 || r.output.find("<html") == std::string::npos)
      GTEST_SKIP() << "chromium cannot run here (exit " << r.exit_code << "): " << test::read_file(dir / "chromium.err").substr(0, 600);
    const std::string state = attribute(r.output, "state", "data-state");
    if (state != "tracking") {
      other_states.push_back(state);
      continue;
    }
    // Labels for people: the title names the station once, rules read as words,
    // and the demo's recording (it has ground truth) says how far off the station is.
    EXPECT_TRUE(r.output.find("<title>demo — spinewatch live view</title>") != std::string::npos)
        << r.output.substr(0, 600);
    EXPECT_EQ(r.output.find(">iso11226_"), std::string::npos) << "a rule shown by its id";
    EXPECT_NE(r.output.find(">trunk inclination (ISO 11226)<"), std::string::npos);
    std::smatch truth;
    ASSERT_TRUE(std::regex_search(r.output, truth, std::regex(R"(every vertebra \(mean\)</td><td>([0-9.]+) mm)")))
        << "no ground-truth figures on the page";
    EXPECT_LE(std::stod(truth[1]), 16.7) << "the demo is further off than docs/accuracy.md states";
    // Legs cut at the bottom are tolerated (docs/daemon.md): shown as fine, not as a warning.
    static const std::regex cut_at_bottom(R"re(<td class="(\w*)">cut at bottom</td>)re");
    for (auto it = std::sregex_iterator(r.output.begin(), r.output.end(), cut_at_bottom);
         it != std::sregex_iterator(); ++it)
      EXPECT_EQ((*it)[1], "ok") << "\"cut at bottom\" shown as " << (*it)[1];
    spines.push_back(attribute(r.output, "spine-side", "data-points"));
    ASSERT_FALSE(spines.back().empty()) << "no spine drawn:\n" << r.output.substr(0, 4000);
    // 17 vertebrae, T1 to L5.
    EXPECT_EQ(std::count(spines.back().begin(), spines.back().end(), ' '), 16) << spines.back();
  }
  ASSERT_GE(spines.size(), 2u) << "pages not tracking: " << other_states.size();
  EXPECT_LE(other_states.size(), 3u) << "the page showed a tracked spine too rarely; it showed: \""
                                    << fmt::format("{}", fmt::join(other_states, "\", \"")) << "\"";
  EXPECT_TRUE(two_differ()) << "the spine view did not change while the phantom bends, over " << spines.size()
                            << " tracked pages";
  EXPECT_GT(frames_written(), frames_before) << "the page's MJPEG stream received no frame";

  const auto png = std::filesystem::path(test::binary_dir()) / "live_view.png";
  std::filesystem::remove(png);
  const auto r = test::run_command(chromium(dir, "--window-size=1280,960 --hide-scrollbars --screenshot='" + png.string() + "'", url) +
                                   " 2>&1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat shot = cv::imread(png.string());
  ASSERT_FALSE(shot.empty()) << r.output;
  EXPECT_EQ(shot.cols, 1280);
  EXPECT_EQ(shot.rows, 960);
  std::printf("screenshot: %s\n", png.c_str());
}

}  // namespace
}  // namespace spinewatch
