// spinewatch deform, fit-spine and fit-cvsm on small files.
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "spine_truth.hpp"
#include "spinewatch/estimator/cvsm/body_model.hpp"
#include "spinewatch/estimator/posture_json.hpp"
#include "spinewatch/estimator/spine/deform_report.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using nlohmann::json;

std::string targets_ndjson(const std::vector<Posture>& truth, bool with_dirs) {
  std::string out;
  for (const Posture& p : truth) {
    json line = {{"seq", p.seq}, {"t_ns", p.t_ns},
                 {"neck", {p.neck->x(), p.neck->y(), p.neck->z()}},
                 {"waist", {p.waist->x(), p.waist->y(), p.waist->z()}}};
    if (with_dirs) {
      line["neck_dir"] = {p.neck_dir->x(), p.neck_dir->y(), p.neck_dir->z()};
      line["waist_dir"] = {p.waist_dir->x(), p.waist_dir->y(), p.waist_dir->z()};
    }
    out += line.dump() + "\n";
  }
  return out;
}

std::vector<Posture> read_postures(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<Posture> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    auto p = decode_posture(line, path.string() + ":" + std::to_string(n));
    EXPECT_TRUE(p) << p.error().message;
    if (p) out.push_back(*p);
  }
  return out;
}

TEST(DeformCli, DeformsASubjectToItsTargets) {
  test::TempDir dir;
  const auto subject = test::make_subject(1600, 1.3);
  const auto truth = test::lateral_sequence(subject, 6);
  test::write_file(dir / "subject.json", subject_to_json(subject.spine));
  test::write_file(dir / "targets.ndjson", targets_ndjson(truth, true));
  const auto r = test::run_cli("deform --subject " + (dir / "subject.json").string() + " --targets " +
                               (dir / "targets.ndjson").string() + " --out " + (dir / "out.ndjson").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(test::validate_ndjson(dir / "out.ndjson"), "");
  const auto out = read_postures(dir / "out.ndjson");
  ASSERT_EQ(out.size(), truth.size());
  const json first = json::parse(test::read_file(dir / "out.ndjson").substr(0, test::read_file(dir / "out.ndjson").find('\n')));
  EXPECT_EQ(first["state"], "tracking");
  EXPECT_EQ(first["fit"]["cost"], 0.0);
  EXPECT_EQ(first["angles"].size(), kJointCount);
  EXPECT_EQ(first["loads"].size(), kVertebraCount);
  EXPECT_EQ(out[3].seq, truth[3].seq);
  const DeformReport report = compare_deformation(out, truth);
  EXPECT_LE(report.overall.mean, 3.0) << format_table(report);
}

TEST(DeformCli, WritesToStandardOutputWithoutDirections) {
  test::TempDir dir;
  const auto subject = test::make_subject(1750, 0.0);
  test::write_file(dir / "subject.json", subject_to_json(subject.spine));
  test::write_file(dir / "targets.ndjson", targets_ndjson({test::truth_posture(subject, 10, 0, 0, 7)}, false));
  const auto r = test::run_cli("deform --subject " + (dir / "subject.json").string() + " --targets " +
                               (dir / "targets.ndjson").string() + " --out - 2>/dev/null");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto p = decode_posture(r.output.substr(0, r.output.find('\n')), "stdout");
  ASSERT_TRUE(p) << p.error().message;
  EXPECT_EQ(p->seq, 7u);
}

TEST(DeformCli, BadInputNamesFileLineAndField) {
  test::TempDir dir;
  const auto subject = test::make_subject(1750, 0.0);
  test::write_file(dir / "subject.json", subject_to_json(subject.spine));
  const std::string good = targets_ndjson({test::truth_posture(subject, 0, 0, 0, 0)}, true);
  struct Case {
    std::string second_line, expected;
  };
  for (const Case& c : {Case{"{\"waist\": [0, 1000, 0]}", "targets.ndjson:2: neck: missing"},
                        Case{"{\"neck\": [0, 1, \"a\"], \"waist\": [0, 0, 0]}", "targets.ndjson:2: neck[2]: not a number"},
                        Case{"{\"neck\": [0, 1, 2], \"waist\": [0, 0, 0], \"neck_dir\": [0, 3, 0]}",
                             "targets.ndjson:2: neck_dir: not a unit vector"},
                        Case{"[1, 2", "targets.ndjson:2: not valid JSON"}}) {
    test::write_file(dir / "targets.ndjson", good + c.second_line + "\n");
    const auto r = test::run_cli("deform --subject " + (dir / "subject.json").string() + " --targets " +
                                 (dir / "targets.ndjson").string() + " --out " + (dir / "out.ndjson").string());
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << r.output;
  }
  test::write_file(dir / "bad_subject.json", "{\"vertebrae\": 3}");
  const auto r = test::run_cli("deform --subject " + (dir / "bad_subject.json").string() + " --targets " +
                               (dir / "targets.ndjson").string() + " --out " + (dir / "out.ndjson").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("bad_subject.json: vertebrae:"), std::string::npos) << r.output;
  EXPECT_EQ(test::run_cli("deform --subject x.json").exit_code, 2);  // missing required options
}

TEST(FitSpineCli, WritesAFragmentDeformAccepts) {
  test::TempDir dir;
  const auto subject = test::make_subject(1600, 1.3);
  std::string truth;
  for (const Posture& p : test::lateral_sequence(subject, 4)) truth += encode_posture(p) + "\n";
  test::write_file(dir / "gt.ndjson", truth);
  test::write_file(dir / "subject.json", subject_to_json(subject.spine));
  auto r = test::run_cli("fit-spine --truth " + (dir / "gt.ndjson").string() + " --subject " +
                         (dir / "subject.json").string() + " --rounds 1 --max-frames 2 --out " +
                         (dir / "fit.toml").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string fragment = test::read_file(dir / "fit.toml");
  EXPECT_NE(fragment.find("[spine.bending_scale]"), std::string::npos);
  EXPECT_NE(fragment.find("\"L4-L5\" = "), std::string::npos);
  test::write_file(dir / "targets.ndjson", targets_ndjson(test::lateral_sequence(subject, 2), true));
  r = test::run_cli("deform --subject " + (dir / "subject.json").string() + " --targets " +
                    (dir / "targets.ndjson").string() + " --stiffness " + (dir / "fit.toml").string() + " --out " +
                    (dir / "out.ndjson").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = test::run_cli("fit-spine --truth " + (dir / "missing.ndjson").string() + " --out " + (dir / "f.toml").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("missing.ndjson: cannot open"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace spinewatch

namespace spinewatch {
namespace {

TEST(FitCvsmCli, FitsTheTemplateAndKeepsItParseable) {
  test::TempDir dir;
  const auto r = test::run_cli("fit-cvsm --out " + (dir / "cvsm.toml").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("fit-cvsm: 6 frame pairs"), std::string::npos) << r.output;
  const std::string text = test::read_file(dir / "cvsm.toml");
  auto parsed = parse_cvsm_spec(text, "cvsm.toml");
  ASSERT_TRUE(parsed) << parsed.error().message;
  EXPECT_NE(text.find("# Sources:"), std::string::npos);  // the comments stay
}

TEST(FitCvsmCli, BadInputIsOneMessageAndExitOne) {
  test::TempDir dir;
  auto r = test::run_cli("fit-cvsm --model " + (dir / "missing.toml").string() + " --out " + (dir / "o.toml").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("missing.toml: cannot open"), std::string::npos) << r.output;
  test::write_file(dir / "bad.toml", "[model]\ncontrol_points = 12\n");
  r = test::run_cli("fit-cvsm --model " + (dir / "bad.toml").string() + " --out " + (dir / "o.toml").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("bad.toml"), std::string::npos) << r.output;
  r = test::run_cli("fit-cvsm --subject " + (dir / "nobody.json").string() + " --out " + (dir / "o.toml").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("nobody.json"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "o.toml"));
}

}  // namespace
}  // namespace spinewatch
