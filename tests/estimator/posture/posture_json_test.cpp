#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "spinewatch/estimator/posture_json.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

Posture tracking_posture() { return test::sample_tracking_posture(); }

TEST(PostureJson, RequiredFieldsInOrderAndNames) {
  const auto j = nlohmann::json::parse(encode_posture(tracking_posture()));
  EXPECT_EQ(j["class"], "posture");
  EXPECT_EQ(j["v"], 1);
  EXPECT_EQ(j["seq"], 17);
  EXPECT_EQ(j["state"], "tracking");
  ASSERT_EQ(j["vertebrae"].size(), 17u);
  EXPECT_EQ(j["vertebrae"][0]["name"], "T1");
  EXPECT_EQ(j["vertebrae"][16]["name"], "L5");
  EXPECT_DOUBLE_EQ(j["fit"]["cost"].get<double>(), 0.031);
  EXPECT_EQ(encode_posture(tracking_posture()).find('\n'), std::string::npos);
}

TEST(PostureJson, LostPostureHasNulls) {
  Posture p;
  p.seq = 3;
  p.state = TrackingState::Lost;
  p.fit.flag = "no_person";
  const auto j = nlohmann::json::parse(encode_posture(p));
  EXPECT_TRUE(j["neck"].is_null());
  EXPECT_TRUE(j["waist"].is_null());
  EXPECT_TRUE(j["vertebrae"].is_null());
  EXPECT_EQ(j["state"], "lost");
}

TEST(PostureJson, DecodeRoundTrip) {
  const Posture p = tracking_posture();
  auto d = decode_posture(encode_posture(p), "line 1");
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d->seq, p.seq);
  EXPECT_EQ(d->t_ns, p.t_ns);
  EXPECT_EQ(d->state, p.state);
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    EXPECT_LT(((*d->vertebrae)[i].body_center - (*p.vertebrae)[i].body_center).norm(), 0.01);
    EXPECT_LT((*d->vertebrae)[i].q.angularDistance((*p.vertebrae)[i].q), 1e-5);
  }
}

// A stream's quaternions carry six decimals, so a unit quaternion's norm
// read back is up to a few 1e-6 from 1. Decoding keeps such a quaternion as
// written: renormalising it would move a sixth decimal, and a line decoded
// and encoded again would differ from the one read (fuzz_posture_line).
TEST(PostureJson, AQuaternionItsDecimalsLeaveOffUnitIsKeptAsWritten) {
  const std::string line = encode_posture(tracking_posture());
  const auto t1 = nlohmann::json::parse(line)["vertebrae"][0]["q"].dump();
  const std::size_t at = line.find(t1);
  ASSERT_NE(at, std::string::npos);
  std::string off_unit = line;
  off_unit.replace(at, t1.size(), "[0.992124,0.12,0.03,0.02]");  // norm 1 + 5.0e-6

  auto decoded = decode_posture(off_unit, "line 1");
  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  const Eigen::Quaterniond q = (*decoded->vertebrae)[0].q;
  EXPECT_EQ(q.w(), 0.992124);
  EXPECT_EQ(q.x(), 0.12);
  const std::string reencoded = encode_posture(*decoded);
  EXPECT_NE(reencoded.find("[0.992124,0.12,0.03,0.02]"), std::string::npos) << reencoded;
  auto again = decode_posture(reencoded, "line 2");
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_EQ(encode_posture(*again), reencoded);
}

TEST(PostureJson, AQuaternionFurtherOffUnitIsNormalised) {
  const std::string line = encode_posture(tracking_posture());
  const auto t1 = nlohmann::json::parse(line)["vertebrae"][0]["q"].dump();
  std::string off_unit = line;
  off_unit.replace(line.find(t1), t1.size(), "[0.9925,0.12,0.03,0.02]");  // norm 1 + 3.7e-4
  auto decoded = decode_posture(off_unit, "line 1");
  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  EXPECT_NEAR((*decoded->vertebrae)[0].q.norm(), 1.0, 1e-12);
}

TEST(PostureJson, DecodeRejectsBadLinesWithWhere) {
  EXPECT_EQ(decode_posture("{", "gt.ndjson:4").error().message, "gt.ndjson:4: not valid JSON");
  EXPECT_EQ(decode_posture(R"({"seq": 1, "t_ns": 0, "state": "sleeping"})", "gt.ndjson:5").error().message,
            "gt.ndjson:5: state: unknown value \"sleeping\"");
  EXPECT_EQ(decode_posture(R"({"seq": 1, "t_ns": 0, "state": "tracking", "neck": [1, 2]})", "g:6").error().message,
            "g:6: neck: expected an array of 3 numbers");
  EXPECT_EQ(decode_posture(R"({"t_ns": 0, "state": "lost"})", "g:7").error().message,
            "g:7: seq: missing or not a non-negative integer");
}

TEST(PostureJson, StreamSkipsHelloAndBlankLinesAndNumbersTheRest) {
  Posture second = tracking_posture();
  second.seq = 18;
  std::istringstream in("{\"class\":\"hello\",\"v\":1}\n" + encode_posture(tracking_posture()) + "\n\n  \r\n" +
                        encode_posture(second) + "\n");
  auto lines = decode_posture_stream(in, "s.ndjson");
  ASSERT_TRUE(lines.ok()) << lines.error().message;
  ASSERT_EQ(lines->size(), 2u);
  EXPECT_EQ((*lines)[0].line, 2u);
  EXPECT_EQ((*lines)[0].posture.seq, 17u);
  EXPECT_EQ((*lines)[1].line, 5u);
  EXPECT_EQ((*lines)[1].posture.seq, 18u);
}

TEST(PostureJson, StreamNamesTheLineThatDoesNotRead) {
  std::istringstream broken(encode_posture(tracking_posture()) + "\n{not json\n");
  auto bad = decode_posture_stream(broken, "s.ndjson");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message, "s.ndjson:2: not valid JSON");

  std::istringstream summaries("{\"class\":\"summary\",\"v\":1}\n");
  auto wrong_file = decode_posture_stream(summaries, "s.ndjson");
  ASSERT_FALSE(wrong_file.ok());
  EXPECT_NE(wrong_file.error().message.find("s.ndjson:1: an exposure summary line"), std::string::npos)
      << wrong_file.error().message;
}

TEST(PostureJson, OutputValidatesAgainstSchema) {
  test::TempDir dir;
  Posture full = tracking_posture();
  full.neck_dir = Eigen::Vector3d(0, 1, 0);
  full.waist_dir = Eigen::Vector3d(0.1, 0.99, 0).normalized();
  full.angles.push_back({"T1-T2", 1.5, -0.5, 0.2});
  full.loads.push_back({"L5", 458.0});
  full.ergonomics = Ergonomics{12.0, 3.0, 1.0, 2, {{"iso11226_trunk_inclination", "ok", 12.0, 0.0}}};
  full.fit.xor_frontal_px = 120;
  full.fit.candidates = 80;
  full.worker = WorkerBody{1755.0, BodyValueSource::Measured, 82.1, BodyValueSource::Estimated, 1550.0, 1500.0, 1040.0};
  Posture lost;
  lost.seq = 18;
  lost.state = TrackingState::Lost;
  std::ofstream out(dir / "stream.ndjson");
  out << encode_posture(tracking_posture()) << '\n' << encode_posture(full) << '\n' << encode_posture(lost) << '\n';
  out.close();
  EXPECT_EQ(test::validate_ndjson(dir / "stream.ndjson"), "");
}

// The validator must be able to fail, or the test above proves nothing.
TEST(PostureJson, SchemaRejectsBrokenLines) {
  test::TempDir dir;
  auto j = to_json(tracking_posture());
  j["vertebrae"].erase(3);
  test::write_file(dir / "a.ndjson", j.dump() + "\n");
  EXPECT_NE(test::validate_ndjson(dir / "a.ndjson"), "");
  auto k = to_json(tracking_posture());
  k["state"] = "lost";  // lost with a posture is a contradiction
  test::write_file(dir / "b.ndjson", k.dump() + "\n");
  EXPECT_NE(test::validate_ndjson(dir / "b.ndjson"), "");
  auto w = to_json(tracking_posture());
  w["worker"] = {{"stature_mm", 1755.0}, {"stature", "guessed"}, {"mass_kg", 80.0}, {"mass", "given"}};
  test::write_file(dir / "c.ndjson", w.dump() + "\n");
  EXPECT_NE(test::validate_ndjson(dir / "c.ndjson"), "");
}

}  // namespace
}  // namespace spinewatch
