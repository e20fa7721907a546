// The real spinewatchd started with the subject already in view (issue 15):
// with the station's stored background it tracks from the start; without
// one it says init / no_background, bootstraps, then tracks; a restart
// mid-stream loses tracking only for the restart. `spinewatch background`
// makes the stored background from a recording's empty frames.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "test_client.hpp"
#include "daemon_process.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;
using test::DaemonProcess;
using test::LineClient;

class DaemonBackground : public ::testing::Test {
 protected:
  // A phantom subject in view from the first frame; its recording carries
  // no background (docs/interfaces.md §2: normal input).
  std::filesystem::path subject_in_view(int frames) {
    const auto rec = dir / "rec";
    auto r = test::run_cli("--log-level warn phantom --subject generic --scenario sway --empty-frames 0 --frames " +
                           std::to_string(frames) + " --out '" + rec.string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    // The empty scene, as an installer captures it: from a recording of
    // the empty station (here: the phantom's scene with nobody in it).
    const auto empty = dir / "empty";
    r = test::run_cli("--log-level warn phantom --subject generic --scenario upright --empty-frames 30 --frames 1 --out '" +
                      empty.string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    r = test::run_cli("background --recording '" + empty.string() + "' --frames 30 --out '" + (dir / "station").string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    for (const char* png : {"background_frontal.png", "background_lateral.png"}) std::filesystem::remove(rec / png);
    return rec;
  }
  std::filesystem::path write_config(const std::filesystem::path& rec, const std::string& silhouette) {
    const auto path = dir / "spinewatch.toml";
    test::write_file(path, "[station]\nname = \"bg\"\n[cameras]\nsource = \"recording\"\nrecording = \"" + rec.string() +
                               "\"\ncalibration = \"/nonexistent/cal.yaml\"\n"
                               // Every pair estimated, however slow the build (these
                               // tests are about the background, not the pacing).
                               "replay = \"fast\"\n[silhouette]\n" + silhouette +
                               "\n[publish]\nclient_queue = 100000\n");
    return path;
  }
  std::string station_background() const {
    return "background_frontal = \"" + (dir / "station" / "background_frontal.png").string() +
           "\"\nbackground_lateral = \"" + (dir / "station" / "background_lateral.png").string() + "\"";
  }
  // The posture lines a client reads from a daemon on this config.
  std::vector<nlohmann::json> postures(const std::filesystem::path& config, int count, std::string* log = nullptr) {
    const auto sock = dir / "p.sock";
    DaemonProcess daemon({test::daemon_path(), "--config", config.string(), "--listen", "none", "--unix", sock.string()},
                         dir / "daemon.log");
    std::optional<LineClient> client;
    for (int i = 0; i < 750 && !client && daemon.running(); ++i) {
      try {
        client.emplace(LineClient::unix_socket(sock));
      } catch (const std::exception&) {
        std::this_thread::sleep_for(20ms);
      }
    }
    std::vector<nlohmann::json> lines;
    if (!client) {
      ADD_FAILURE() << "no connection\n" << daemon.log();
      return lines;
    }
    EXPECT_TRUE(client->read_line(test::scaled(5s)));  // hello
    while (static_cast<int>(lines.size()) < count) {
      auto line = client->read_line(test::scaled(5s));
      if (!line) break;
      auto j = nlohmann::json::parse(*line);
      if (j.value("class", "") == "posture") lines.push_back(std::move(j));  // summaries come at whole minutes
    }
    daemon.signal(SIGTERM);
    EXPECT_EQ(daemon.wait_exit(test::scaled(5s)), 0) << daemon.log();
    if (log) *log = daemon.log();
    return lines;
  }
  static std::string state(const nlohmann::json& p) { return p.at("state").get<std::string>(); }
  static std::string flag(const nlohmann::json& p) {
    return p.contains("fit") && p["fit"].contains("flag") ? p["fit"]["flag"].get<std::string>() : "";
  }
  test::TempDir dir;
};

TEST_F(DaemonBackground, WithTheStationsBackgroundItTracksFromTheStartAndAfterARestart) {
  const auto rec = subject_in_view(150);
  const auto config = write_config(rec, station_background());
  for (int run = 0; run < 2; ++run) {  // the second run: the daemon restarted with the worker still there
    std::string log;
    const auto lines = postures(config, 60, &log);
    ASSERT_EQ(lines.size(), 60U) << log;
    int first_tracking = -1;
    for (int i = 0; i < 60; ++i) {
      EXPECT_NE(flag(lines[i]), "no_background") << "line " << i;
      EXPECT_NE(state(lines[i]), "lost") << "line " << i << ": " << lines[i].dump();
      if (first_tracking < 0 && state(lines[i]) == "tracking") first_tracking = i;
    }
    // Only the subject model's frames (cvsm.subject_frames = 10) are init.
    EXPECT_GE(first_tracking, 0) << log;
    EXPECT_LE(first_tracking, 10) << "run " << run;
    EXPECT_GT(lines.back().at("stats").at("background_updates").get<int>(), 0);
    EXPECT_EQ(lines.back().at("stats").at("background_bootstraps").get<int>(), 0);
    EXPECT_NE(log.find("background: " + (dir / "station" / "background_frontal.png").string()), std::string::npos) << log;
  }
}

TEST_F(DaemonBackground, WithoutOneItSaysNoBackgroundThenBootstrapsAndTracks) {
  const auto rec = subject_in_view(150);
  const auto config = write_config(rec, "");
  std::string log;
  const auto lines = postures(config, 120, &log);
  ASSERT_EQ(lines.size(), 120U) << log;
  int first_tracking = -1, no_background = 0;
  for (int i = 0; i < 120; ++i) {
    if (flag(lines[i]) == "no_background") {
      ++no_background;
      EXPECT_EQ(state(lines[i]), "init") << "line " << i;
      EXPECT_TRUE(lines[i].at("neck").is_null()) << "no posture is invented without a background";
      EXPECT_LT(first_tracking, 0) << "no_background after tracking began, line " << i;
    }
    if (first_tracking < 0 && state(lines[i]) == "tracking") first_tracking = i;
  }
  EXPECT_GT(no_background, 0) << "the first pairs have no background and say so";
  ASSERT_GE(first_tracking, 0) << log;
  EXPECT_LT(first_tracking, 90) << "tracking within 3 s";
  EXPECT_EQ(lines.back().at("stats").at("background_bootstraps").get<int>(), 2) << "both views";
  // Logged once, with what to do.
  const auto warning = log.find("no background and the scene is not empty");
  ASSERT_NE(warning, std::string::npos) << log;
  EXPECT_EQ(log.find("no background and the scene is not empty", warning + 1), std::string::npos) << log;
  EXPECT_NE(log.find("spinewatch background"), std::string::npos);
}

TEST_F(DaemonBackground, ImageModeWithoutImagesIsRefusedAtStart) {
  const auto rec = subject_in_view(5);
  const auto config = write_config(rec, "background = \"image\"");
  auto r = test::run_command(test::daemon_path() + " --config '" + config.string() + "' --listen none --unix '" + (dir / "s.sock").string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("silhouette.background = \"image\" needs silhouette.background_frontal"), std::string::npos)
      << r.output;
  const auto bad = write_config(rec, "background_frontal = \"/nonexistent/f.png\"\nbackground_lateral = \"/nonexistent/l.png\"");
  r = test::run_command(test::daemon_path() + " --config '" + bad.string() + "' --listen none --unix '" + (dir / "s.sock").string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("/nonexistent/f.png: no such file"), std::string::npos) << r.output;
}

TEST_F(DaemonBackground, BackgroundCommandRefusesASceneWithSomeoneMoving) {
  const auto rec = subject_in_view(40);
  auto r = test::run_cli("background --recording '" + rec.string() + "' --frames 30 --out '" + (dir / "x").string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("the scene was not empty or not still"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "x" / "background_frontal.png"));
}

}  // namespace
}  // namespace spinewatch
