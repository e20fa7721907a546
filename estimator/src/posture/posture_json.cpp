#include "spinewatch/estimator/posture_json.hpp"

#include <cmath>
#include <istream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/json_number.hpp"

namespace spinewatch {
namespace {
using nlohmann::json;
// Output keeps the documented field order (class, v, seq, … as in docs/interfaces.md §3).
using ojson = nlohmann::ordered_json;

// Positions to 0.01 mm and quaternions to 1e-6 are far below what the
// method resolves, and keep lines short.
using detail::round_to;

ojson vec3(const Eigen::Vector3d& v, double quantum = 0.01) {
  return ojson::array({round_to(v.x(), quantum), round_to(v.y(), quantum), round_to(v.z(), quantum)});
}
ojson quat(const Eigen::Quaterniond& q) {
  return ojson::array({round_to(q.w(), 1e-6), round_to(q.x(), 1e-6), round_to(q.y(), 1e-6), round_to(q.z(), 1e-6)});
}

Result<Eigen::Vector3d> read_vec3(const json& j, std::string_view where, std::string_view key) {
  if (!j.is_array() || j.size() != 3)
    return Error{fmt::format("{}: {}: expected an array of 3 numbers", where, key)};
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) {
    if (!j[static_cast<std::size_t>(i)].is_number())
      return Error{fmt::format("{}: {}[{}]: not a number", where, key, i)};
    v[i] = j[static_cast<std::size_t>(i)].get<double>();
  }
  return v;
}

Result<Eigen::Quaterniond> read_quat(const json& j, std::string_view where, std::string_view key) {
  if (!j.is_array() || j.size() != 4)
    return Error{fmt::format("{}: {}: expected [w, x, y, z]", where, key)};
  double c[4];
  for (std::size_t i = 0; i < 4; ++i) {
    if (!j[i].is_number()) return Error{fmt::format("{}: {}[{}]: not a number", where, key, i)};
    c[i] = j[i].get<double>();
  }
  Eigen::Quaterniond q(c[0], c[1], c[2], c[3]);
  if (std::abs(q.norm() - 1.0) > 1e-3)
    return Error{fmt::format("{}: {}: not a unit quaternion (norm {:.4f})", where, key, q.norm())};
  // Kept as written when the stream's six decimals explain the norm's
  // distance from 1 (each component rounded by 5e-7): normalising such a
  // quaternion moves a sixth decimal, and a re-encoded line would differ
  // from the one read (found by fuzz_posture_line).
  if (std::abs(q.norm() - 1.0) > 1e-5) q.normalize();
  return q;
}

}  // namespace

std::string_view to_string(TrackingState state) {
  switch (state) {
    case TrackingState::Init: return "init";
    case TrackingState::Tracking: return "tracking";
    case TrackingState::Lost: return "lost";
  }
  return "lost";
}

ojson to_json(const Posture& p) {
  ojson j;
  j["class"] = "posture";
  j["v"] = kPostureSchemaVersion;
  j["seq"] = p.seq;
  j["t_ns"] = p.t_ns;
  j["state"] = to_string(p.state);
  j["neck"] = p.neck ? vec3(*p.neck) : ojson(nullptr);
  j["waist"] = p.waist ? vec3(*p.waist) : ojson(nullptr);
  if (p.vertebrae) {
    ojson list = ojson::array();
    for (std::size_t i = 0; i < kVertebraCount; ++i)
      list.push_back({{"name", kVertebraNames[i]},
                      {"body_center", vec3((*p.vertebrae)[i].body_center)},
                      {"q", quat((*p.vertebrae)[i].q)}});
    j["vertebrae"] = std::move(list);
  } else {
    j["vertebrae"] = nullptr;
  }
  ojson fit = {{"cost", round_to(p.fit.cost, 1e-6)}};
  if (p.fit.xor_frontal_px) fit["xor_frontal_px"] = *p.fit.xor_frontal_px;
  if (p.fit.xor_lateral_px) fit["xor_lateral_px"] = *p.fit.xor_lateral_px;
  if (p.fit.silhouette_frontal_px) fit["silhouette_frontal_px"] = *p.fit.silhouette_frontal_px;
  if (p.fit.silhouette_lateral_px) fit["silhouette_lateral_px"] = *p.fit.silhouette_lateral_px;
  if (p.fit.candidates) fit["candidates"] = *p.fit.candidates;
  if (p.fit.flag) fit["flag"] = *p.fit.flag;
  j["fit"] = std::move(fit);
  j["latency_us"] = p.latency_us;

  if (p.neck_dir) j["neck_dir"] = vec3(*p.neck_dir, 1e-6);
  if (p.waist_dir) j["waist_dir"] = vec3(*p.waist_dir, 1e-6);
  if (!p.angles.empty()) {
    ojson a = ojson::array();
    for (const auto& l : p.angles)
      a.push_back({{"level", l.level}, {"flexion", round_to(l.flexion, 0.01)},
                   {"lateral", round_to(l.lateral, 0.01)}, {"twist", round_to(l.twist, 0.01)}});
    j["angles"] = std::move(a);
  }
  if (!p.loads.empty()) {
    ojson a = ojson::array();
    for (const auto& l : p.loads) a.push_back({{"level", l.level}, {"compression_n", round_to(l.compression_n, 0.1)}});
    j["loads"] = std::move(a);
  }
  if (p.ergonomics) {
    const auto& e = *p.ergonomics;
    ojson flags = ojson::array();
    for (const auto& f : e.flags)
      flags.push_back({{"rule", f.rule}, {"severity", f.severity}, {"value", round_to(f.value, 0.01)},
                       {"held_s", round_to(f.held_s, 0.01)}});
    j["ergonomics"] = {{"trunk_inclination_deg", round_to(e.trunk_inclination_deg, 0.01)},
                       {"lateral_bend_deg", round_to(e.lateral_bend_deg, 0.01)},
                       {"twist_deg", round_to(e.twist_deg, 0.01)},
                       {"reba_trunk", e.reba_trunk},
                       {"flags", std::move(flags)}};
  }
  if (p.worker) {
    const WorkerBody& w = *p.worker;
    j["worker"] = {{"stature_mm", round_to(w.stature_mm, 0.1)},
                   {"stature", to_string(w.stature_source)},
                   {"mass_kg", round_to(w.mass_kg, 0.1)},
                   {"mass", to_string(w.mass_source)}};
    if (w.rejected_stature_mm) j["worker"]["rejected_stature_mm"] = round_to(*w.rejected_stature_mm, 0.1);
    if (w.c7_height_mm) j["worker"]["c7_height_mm"] = round_to(*w.c7_height_mm, 0.1);
    if (w.iliac_crest_height_mm) j["worker"]["iliac_crest_height_mm"] = round_to(*w.iliac_crest_height_mm, 0.1);
  }
  return j;
}

std::string encode_posture(const Posture& posture) { return to_json(posture).dump(); }

Result<Posture> decode_posture(std::string_view line, std::string_view where) {
  json j = json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return Error{fmt::format("{}: not valid JSON", where)};
  return posture_from_json(j, where);
}

Result<Posture> posture_from_json(const json& j, std::string_view where) {
  if (!j.is_object()) return Error{fmt::format("{}: not a JSON object", where)};
  Posture p;
  auto field = [&](const char* key) -> const json* {
    auto it = j.find(key);
    return it == j.end() ? nullptr : &*it;
  };
  if (const json* seq = field("seq"); seq && seq->is_number_unsigned()) p.seq = seq->get<std::uint64_t>();
  else if (seq && seq->is_number_integer() && seq->get<std::int64_t>() >= 0) p.seq = seq->get<std::uint64_t>();
  else return Error{fmt::format("{}: seq: missing or not a non-negative integer", where)};
  if (const json* t = field("t_ns"); t && t->is_number_integer()) p.t_ns = t->get<std::int64_t>();
  else return Error{fmt::format("{}: t_ns: missing or not an integer", where)};
  const json* state = field("state");
  if (!state || !state->is_string()) return Error{fmt::format("{}: state: missing", where)};
  const std::string s = state->get<std::string>();
  if (s == "tracking") p.state = TrackingState::Tracking;
  else if (s == "init") p.state = TrackingState::Init;
  else if (s == "lost") p.state = TrackingState::Lost;
  else return Error{fmt::format("{}: state: unknown value \"{}\"", where, s)};

  for (auto [key, target] : {std::pair{"neck", &p.neck}, std::pair{"waist", &p.waist},
                             std::pair{"neck_dir", &p.neck_dir}, std::pair{"waist_dir", &p.waist_dir}}) {
    const json* v = field(key);
    if (!v || v->is_null()) continue;
    auto r = read_vec3(*v, where, key);
    if (!r) return r.error();
    *target = *r;
  }
  if (const json* list = field("vertebrae"); list && !list->is_null()) {
    if (!list->is_array() || list->size() != kVertebraCount)
      return Error{fmt::format("{}: vertebrae: expected {} entries T1…L5", where, kVertebraCount)};
    SpinePose pose;
    for (std::size_t i = 0; i < kVertebraCount; ++i) {
      const json& v = (*list)[i];
      const std::string key = fmt::format("vertebrae[{}]", i);
      if (!v.is_object() || !v.contains("name") || v["name"] != kVertebraNames[i])
        return Error{fmt::format("{}: {}: expected name \"{}\"", where, key, kVertebraNames[i])};
      auto c = read_vec3(v.value("body_center", json()), where, key + ".body_center");
      if (!c) return c.error();
      auto q = read_quat(v.value("q", json()), where, key + ".q");
      if (!q) return q.error();
      pose[i] = {*c, *q};
    }
    p.vertebrae = pose;
  }
  if (const json* fit = field("fit"); fit && fit->is_object()) {
    if (auto c = fit->find("cost"); c != fit->end() && c->is_number()) p.fit.cost = c->get<double>();
  }
  if (const json* lat = field("latency_us"); lat && lat->is_number_integer()) p.latency_us = lat->get<std::int64_t>();
  return p;
}

Result<std::vector<NumberedPosture>> decode_posture_stream(std::istream& in, std::string_view source) {
  std::vector<NumberedPosture> postures;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = fmt::format("{}:{}", source, number);
    const auto j = json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded()) return Error{fmt::format("{}: not valid JSON", where)};
    if (j.is_object() && j.value("class", "") == "hello") continue;
    // The other line a station writes, given where postures were meant.
    if (j.is_object() && j.value("class", "") == "summary")
      return Error{fmt::format("{}: an exposure summary line: this is a summaries file (replay --summaries, read by "
                               "spinewatch report --summaries), not a posture stream; give the file replay --out wrote",
                               where)};
    auto posture = posture_from_json(j, where);
    if (!posture) return posture.error();
    postures.push_back({number, std::move(posture).value()});
  }
  return postures;
}

}  // namespace spinewatch
