// The CLI's video and image files go through the media module
// (tools/media, spinewatch-media.so), loaded only by the commands that
// read or write them: the CLI itself links none of OpenCV's videoio and
// imgcodecs, an installed CLI finds the module beside it, and one that
// cannot says which file is missing and how to get it back.
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace spinewatch {
namespace {

namespace fs = std::filesystem;

// The module in this build tree, at <build>/<libdir>/spinewatch/ as a
// package installs it at <prefix>/<libdir>/spinewatch/ (<libdir>:
// lib/<arch> with the /usr prefix of the release presets, lib without one).
fs::path built_module() {
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(test::binary_dir()) / "lib"))
    if (entry.path().filename() == "spinewatch-media.so") return entry.path();
  return {};
}

// A directory outside the build tree (test::TempDir's are inside it),
// removed with everything in it.
struct OutsideDir {
  fs::path path = fs::temp_directory_path() / ("spinewatch-media-test-" + std::to_string(::getpid()));
  OutsideDir() { fs::remove_all(path); }
  ~OutsideDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

TEST(MediaModule, TheCliLinksNoVideoOrImageCodecs) {
  const auto ldd = test::run_command("ldd " + test::cli_path());
  ASSERT_EQ(ldd.exit_code, 0) << ldd.output;
  EXPECT_NE(ldd.output.find("libopencv_core"), std::string::npos) << ldd.output;
  EXPECT_EQ(ldd.output.find("libopencv_videoio"), std::string::npos) << ldd.output;
  EXPECT_EQ(ldd.output.find("libopencv_imgcodecs"), std::string::npos) << ldd.output;
}

TEST(MediaModule, AnInstalledCliLoadsTheModuleBesideItAndNamesItWhenMissing) {
  const fs::path module = built_module();
  ASSERT_FALSE(module.empty()) << "no spinewatch-media.so under " << test::binary_dir() << "/lib";
  // Outside the build tree, as a package installs it: <root>/usr/bin/spinewatch.
  const OutsideDir outside;
  const fs::path& root = outside.path;
  fs::create_directories(root / "usr/bin");
  const fs::path cli = root / "usr/bin/spinewatch";
  fs::copy_file(test::cli_path(), cli);
  const fs::path installed = root / "usr" / fs::relative(module, test::binary_dir());
  const fs::path board = root / "board.png";
  const std::string write_board = cli.string() + " calibrate --write-board " + board.string() + " --dpi 20";

  const auto missing = test::run_command(write_board);
  EXPECT_NE(missing.exit_code, 0) << missing.output;
  EXPECT_NE(missing.output.find(installed.string() + ": the media module (video and image files) could not be loaded"),
            std::string::npos)
      << missing.output;
  EXPECT_NE(missing.output.find("reinstall it"), std::string::npos) << missing.output;
  EXPECT_FALSE(fs::exists(board));
  // Commands without files to read or write do not need it.
  EXPECT_EQ(test::run_command(cli.string() + " --version").exit_code, 0);

  fs::create_directories(installed.parent_path());
  fs::copy_file(module, installed);
  const auto found = test::run_command(write_board);
  EXPECT_EQ(found.exit_code, 0) << found.output;
  EXPECT_GT(fs::exists(board) ? fs::file_size(board) : 0, 1000u);
}

}  // namespace
}  // namespace spinewatch
