#include "spinewatch/phantom/subject.hpp"

#include <cmath>
#include <initializer_list>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "spinewatch/capture/json_text.hpp"
#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/frames/printable.hpp"
#include "spinewatch/frames/text_file.hpp"

namespace spinewatch::phantom {
namespace {
using nlohmann::json;

// Reads one object level and reports problems as "SOURCE: path.key: problem".
class FieldReader {
 public:
  FieldReader(const json& object, std::string_view source, std::string path)
      : object_(object), source_(source), path_(std::move(path)) {}

  std::string where(std::string_view key) const {
    return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
  }
  // The key may be the file's own (an unknown field): quoted through
  // printable(), so that a line end in it cannot split the message (the
  // phantom_subject fuzzer found it).
  Error error(std::string_view key, std::string_view problem) const {
    return Error{fmt::format("{}: {}: {}", source_, where(printable(key)), problem)};
  }

  // Typos in a subject file would otherwise be silently ignored.
  Status only(std::initializer_list<std::string_view> keys) const {
    for (const auto& [key, value] : object_.items()) {
      bool known = false;
      for (auto k : keys) known = known || k == key;
      if (!known) return error(key, "unknown field");
    }
    return Ok{};
  }

  Result<double> number(std::string_view key, double min, double max) const {
    auto it = object_.find(key);
    if (it == object_.end()) return error(key, "missing");
    if (!it->is_number()) return error(key, "expected a number");
    const double v = it->get<double>();
    if (!(v >= min && v <= max)) return error(key, fmt::format("{} is out of range [{}, {}]", v, min, max));
    return v;
  }

  Result<FieldReader> object(std::string_view key) const {
    auto it = object_.find(key);
    if (it == object_.end()) return error(key, "missing");
    if (!it->is_object()) return error(key, "expected an object");
    return FieldReader(*it, source_, where(key));
  }

  const json& raw() const { return object_; }
  std::string_view source() const { return source_; }

 private:
  const json& object_;
  std::string_view source_;
  std::string path_;
};

// Reads {key: number} pairs of one object into the given fields.
struct NumberField {
  const char* key;
  double* out;
  double min, max;
};
Status read_numbers(const FieldReader& r, std::initializer_list<NumberField> fields) {
  for (const NumberField& f : fields) {
    auto v = r.number(f.key, f.min, f.max);
    if (!v) return v.error();
    *f.out = *v;
  }
  return Ok{};
}

// An object of numbers only: every field required, nothing else allowed.
Status read_group(const FieldReader& root, const char* key, std::initializer_list<NumberField> fields) {
  auto r = root.object(key);
  if (!r) return r.error();
  for (const auto& [name, value] : r->raw().items()) {
    bool known = false;
    for (const NumberField& f : fields) known = known || name == f.key;
    if (!known) return r->error(name, "unknown field");
  }
  return read_numbers(*r, fields);
}

Status read_section(const FieldReader& trunk, const char* key, Section& out) {
  auto r = trunk.object(key);
  if (!r) return r.error();
  if (auto s = r->only({"half_width_mm", "half_depth_mm"}); !s) return s;
  return read_numbers(*r, {{"half_width_mm", &out.half_width_mm, 40, 400}, {"half_depth_mm", &out.half_depth_mm, 40, 300}});
}

Status read_joint_factors(const FieldReader& root, Subject& subject) {
  auto it = root.raw().find("joint_factors");
  if (it == root.raw().end() || it->is_null()) return Ok{};
  if (!it->is_array() || it->size() != kJointCount)
    return root.error("joint_factors", fmt::format("expected {} entries T1-T2…L4-L5", kJointCount));
  std::array<JointAngles, kJointCount> factors;
  for (std::size_t i = 0; i < kJointCount; ++i) {
    const std::string path = fmt::format("joint_factors[{}]", i);
    if (!(*it)[i].is_object()) return Error{fmt::format("{}: {}: expected an object", root.source(), path)};
    FieldReader r((*it)[i], root.source(), path);
    if (auto s = r.only({"flexion", "lateral", "twist"}); !s) return s;
    if (auto s = read_numbers(r, {{"flexion", &factors[i].flexion, 0.1, 10}, {"lateral", &factors[i].lateral, 0.1, 10},
                                  {"twist", &factors[i].twist, 0.1, 10}});
        !s)
      return s;
  }
  subject.joint_factors = factors;
  return Ok{};
}

// An optional number: absent (or null) leaves `out` empty.
Status optional_number(const FieldReader& r, const char* key, double min, double max, std::optional<double>& out) {
  auto it = r.raw().find(key);
  if (it == r.raw().end() || it->is_null()) return Ok{};
  auto v = r.number(key, min, max);
  if (!v) return v.error();
  out = *v;
  return Ok{};
}

// A measured person's landmarks, each optional, checked against the
// height and against each other so that the body stays a body.
Status read_landmarks(const FieldReader& root, Subject& subject) {
  const double h = subject.height_mm;
  const SpinePose generic = neutral_pose(generic_spine_spec(), h);
  const double generic_t1 = generic[kNeckIndex].body_center.y(), generic_l5 = generic[kWaistIndex].body_center.y();
  const double span = generic_t1 - generic_l5;
  if (auto it = root.raw().find("spine_heights_mm"); it != root.raw().end() && !it->is_null()) {
    auto r = root.object("spine_heights_mm");
    if (!r) return r.error();
    if (auto s = r->only({"t1", "l5"}); !s) return s;
    double t1 = 0, l5 = 0;
    if (auto s = read_numbers(*r, {{"t1", &t1, 0.6 * h, 0.95 * h}, {"l5", &l5, 0.4 * h, 0.75 * h}}); !s) return s;
    // A T1–L5 span outside half to twice the generic one at this height
    // is a typo, not a body.
    if (t1 - l5 < 0.5 * span || t1 - l5 > 2 * span)
      return r->error("t1", fmt::format("T1 {} mm above L5 is outside [{:.0f}, {:.0f}]", t1 - l5, 0.5 * span, 2 * span));
    subject.t1_height_mm = t1;
    subject.l5_height_mm = l5;
  }
  if (auto s = optional_number(root, "shoulder_height_mm", 0.6 * h, 0.95 * h, subject.shoulder_height_mm); !s) return s;
  if (auto s = optional_number(root, "hip_joint_height_mm", 0.3 * h, 0.7 * h, subject.hip_joint_height_mm); !s) return s;
  if (auto s = optional_number(root, "sitting_height_mm", 0.4 * h, 0.65 * h, subject.sitting_height_mm); !s) return s;
  // The shoulder ring is drawn about T1 and the hip joints hang from L5:
  // keep them where those solids can reach.
  const double t1 = subject.t1_height_mm.value_or(generic_t1), l5 = subject.l5_height_mm.value_or(generic_l5);
  if (subject.shoulder_height_mm && std::abs(*subject.shoulder_height_mm - t1) > 0.08 * h)
    return root.error("shoulder_height_mm", fmt::format("{} is more than {:.0f} mm from T1 ({:.0f})",
                                                        *subject.shoulder_height_mm, 0.08 * h, t1));
  if (subject.hip_joint_height_mm && (l5 - *subject.hip_joint_height_mm < 0.02 * h || l5 - *subject.hip_joint_height_mm > 0.15 * h))
    return root.error("hip_joint_height_mm", fmt::format("{} must lie {:.0f}–{:.0f} mm below L5 ({:.0f})",
                                                         *subject.hip_joint_height_mm, 0.02 * h, 0.15 * h, l5));
  return Ok{};
}

}  // namespace

std::string_view to_string(SubjectPosture posture) {
  return posture == SubjectPosture::Seated ? "seated" : "standing";
}

Result<Subject> parse_subject(const json& j, std::string_view source) {
  if (!j.is_object()) return Error{fmt::format("{}: expected a JSON object", source)};
  const FieldReader root(j, source, "");
  if (auto s = root.only({"name", "height_mm", "mass_kg", "posture", "trunk", "shoulder_width_mm", "neck", "head", "arms",
                          "legs", "spine_depth_mm", "seat_height_mm", "joint_factors", "spine_heights_mm",
                          "shoulder_height_mm", "hip_joint_height_mm", "sitting_height_mm"});
      !s)
    return s.error();
  Subject subject;
  if (auto it = j.find("name"); it != j.end()) {
    if (!it->is_string()) return root.error("name", "expected a string");
    subject.name = it->get<std::string>();
  }
  // The spine model is defined for 1000–2300 mm (config/spine-generic.toml).
  if (auto s = read_numbers(root, {{"height_mm", &subject.height_mm, 1000, 2300}, {"mass_kg", &subject.mass_kg, 20, 250},
                                   {"shoulder_width_mm", &subject.shoulder_width_mm, 200, 700},
                                   {"seat_height_mm", &subject.seat_height_mm, 250, 900}});
      !s)
    return s.error();

  auto posture = j.find("posture");
  if (posture == j.end()) return root.error("posture", "missing");
  if (*posture == "standing") subject.posture = SubjectPosture::Standing;
  else if (*posture == "seated") subject.posture = SubjectPosture::Seated;
  else return root.error("posture", fmt::format("{} is not \"standing\" or \"seated\"", posture->dump()));

  auto trunk = root.object("trunk");
  if (!trunk) return trunk.error();
  if (auto s = trunk->only({"chest", "waist", "hips"}); !s) return s.error();
  for (auto [key, section] : {std::pair{"chest", &subject.chest}, std::pair{"waist", &subject.waist},
                              std::pair{"hips", &subject.hips}})
    if (auto s = read_section(*trunk, key, *section); !s) return s.error();

  if (auto s = read_group(root, "neck", {{"radius_mm", &subject.neck_radius_mm, 20, 120},
                                         {"length_mm", &subject.neck_length_mm, 10, 250}});
      !s)
    return s.error();
  if (auto s = read_group(root, "head", {{"half_width_mm", &subject.head_half_width_mm, 40, 150},
                                         {"half_depth_mm", &subject.head_half_depth_mm, 40, 150},
                                         {"half_height_mm", &subject.head_half_height_mm, 60, 200}});
      !s)
    return s.error();
  if (auto s = read_group(root, "arms", {{"length_mm", &subject.arm_length_mm, 300, 1200},
                                         {"upper_radius_mm", &subject.upper_arm_radius_mm, 15, 120},
                                         {"lower_radius_mm", &subject.forearm_radius_mm, 10, 100}});
      !s)
    return s.error();
  if (auto s = read_group(root, "legs", {{"length_mm", &subject.leg_length_mm, 400, 1400},
                                         {"thigh_radius_mm", &subject.thigh_radius_mm, 30, 200},
                                         {"shin_radius_mm", &subject.shin_radius_mm, 20, 150}});
      !s)
    return s.error();

  // Either one figure for the whole spine or {"thoracic": …, "lumbar": …}.
  auto depth = j.find("spine_depth_mm");
  if (depth == j.end()) return root.error("spine_depth_mm", "missing");
  if (depth->is_number()) {
    auto v = root.number("spine_depth_mm", 20, 150);
    if (!v) return v.error();
    subject.spine_depth_thoracic_mm = subject.spine_depth_lumbar_mm = *v;
  } else {
    auto r = root.object("spine_depth_mm");
    if (!r) return root.error("spine_depth_mm", "expected a number or {\"thoracic\": …, \"lumbar\": …}");
    if (auto s = r->only({"thoracic", "lumbar"}); !s) return s.error();
    if (auto s = read_numbers(*r, {{"thoracic", &subject.spine_depth_thoracic_mm, 20, 150},
                                   {"lumbar", &subject.spine_depth_lumbar_mm, 20, 150}});
        !s)
      return s.error();
  }
  // The spine must lie inside the trunk, behind its front surface.
  if (subject.spine_depth_thoracic_mm >= 2 * subject.chest.half_depth_mm - 20)
    return root.error("spine_depth_mm.thoracic", "puts the spine outside the chest (must be < 2 × chest.half_depth_mm − 20)");
  if (subject.spine_depth_lumbar_mm >= 2 * subject.waist.half_depth_mm - 20)
    return root.error("spine_depth_mm.lumbar", "puts the spine outside the waist (must be < 2 × waist.half_depth_mm − 20)");

  if (auto s = read_joint_factors(root, subject); !s) return s.error();
  if (auto s = read_landmarks(root, subject); !s) return s.error();
  return subject;
}

Result<Subject> load_subject(const std::filesystem::path& path) {
  auto text = read_text_file(path);
  if (!text) return text.error();
  auto j = parse_json_text(*text);
  if (!j) return Error{fmt::format("{}: not valid JSON: {}", path.string(), j.error().message)};
  return parse_subject(*j, path.string());
}

json to_json(const Subject& s) {
  auto section = [](const Section& x) { return json{{"half_width_mm", x.half_width_mm}, {"half_depth_mm", x.half_depth_mm}}; };
  json j = {
      {"name", s.name},
      {"height_mm", s.height_mm},
      {"mass_kg", s.mass_kg},
      {"posture", to_string(s.posture)},
      {"trunk", {{"chest", section(s.chest)}, {"waist", section(s.waist)}, {"hips", section(s.hips)}}},
      {"shoulder_width_mm", s.shoulder_width_mm},
      {"neck", {{"radius_mm", s.neck_radius_mm}, {"length_mm", s.neck_length_mm}}},
      {"head", {{"half_width_mm", s.head_half_width_mm}, {"half_depth_mm", s.head_half_depth_mm},
                {"half_height_mm", s.head_half_height_mm}}},
      {"arms", {{"length_mm", s.arm_length_mm}, {"upper_radius_mm", s.upper_arm_radius_mm},
                {"lower_radius_mm", s.forearm_radius_mm}}},
      {"legs", {{"length_mm", s.leg_length_mm}, {"thigh_radius_mm", s.thigh_radius_mm}, {"shin_radius_mm", s.shin_radius_mm}}},
      {"spine_depth_mm", {{"thoracic", s.spine_depth_thoracic_mm}, {"lumbar", s.spine_depth_lumbar_mm}}},
      {"seat_height_mm", s.seat_height_mm},
  };
  if (s.t1_height_mm && s.l5_height_mm) j["spine_heights_mm"] = {{"t1", *s.t1_height_mm}, {"l5", *s.l5_height_mm}};
  if (s.shoulder_height_mm) j["shoulder_height_mm"] = *s.shoulder_height_mm;
  if (s.hip_joint_height_mm) j["hip_joint_height_mm"] = *s.hip_joint_height_mm;
  if (s.sitting_height_mm) j["sitting_height_mm"] = *s.sitting_height_mm;
  if (s.joint_factors) {
    json list = json::array();
    for (const auto& f : *s.joint_factors) list.push_back({{"flexion", f.flexion}, {"lateral", f.lateral}, {"twist", f.twist}});
    j["joint_factors"] = std::move(list);
  }
  return j;
}

}  // namespace spinewatch::phantom
