#include "spinewatch/anthropometry/ansur.hpp"

#include <charconv>
#include <cmath>
#include <unordered_set>

#include <fmt/format.h>

#include "spinewatch/anthropometry/csv.hpp"
#include "spinewatch/frames/text_file.hpp"

namespace spinewatch::anthropometry {
namespace {

// A measurement column: its ANSUR name, where it goes, and the factor to
// mm or kg (weightkg is recorded in tenths of a kilogram).
struct Column {
  const char* name;
  double AnsurSubject::*field;
  double scale = 1.0;
};

constexpr Column kColumns[] = {
    {"stature", &AnsurSubject::stature_mm},
    {"cervicaleheight", &AnsurSubject::cervicale_height_mm},
    {"suprasternaleheight", &AnsurSubject::suprasternale_height_mm},
    {"acromialheight", &AnsurSubject::acromial_height_mm},
    {"iliocristaleheight", &AnsurSubject::iliocristale_height_mm},
    {"trochanterionheight", &AnsurSubject::trochanterion_height_mm},
    {"crotchheight", &AnsurSubject::crotch_height_mm},
    {"sittingheight", &AnsurSubject::sitting_height_mm},
    {"biacromialbreadth", &AnsurSubject::biacromial_breadth_mm},
    {"bideltoidbreadth", &AnsurSubject::bideltoid_breadth_mm},
    {"chestbreadth", &AnsurSubject::chest_breadth_mm},
    {"waistbreadth", &AnsurSubject::waist_breadth_mm},
    {"hipbreadth", &AnsurSubject::hip_breadth_mm},
    {"chestdepth", &AnsurSubject::chest_depth_mm},
    {"waistdepth", &AnsurSubject::waist_depth_mm},
    {"buttockdepth", &AnsurSubject::buttock_depth_mm},
    {"neckcircumferencebase", &AnsurSubject::neck_circumference_base_mm},
    {"headbreadth", &AnsurSubject::head_breadth_mm},
    {"headlength", &AnsurSubject::head_length_mm},
    {"tragiontopofhead", &AnsurSubject::tragion_top_of_head_mm},
    {"acromionradialelength", &AnsurSubject::acromion_radiale_length_mm},
    {"radialestylionlength", &AnsurSubject::radiale_stylion_length_mm},
    {"handlength", &AnsurSubject::hand_length_mm},
    {"thighcircumference", &AnsurSubject::thigh_circumference_mm},
    {"calfcircumference", &AnsurSubject::calf_circumference_mm},
    {"bicepscircumferenceflexed", &AnsurSubject::biceps_circumference_mm},
    {"forearmcircumferenceflexed", &AnsurSubject::forearm_circumference_mm},
    {"poplitealheight", &AnsurSubject::popliteal_height_mm},
    {"weightkg", &AnsurSubject::mass_kg, 0.1},
};

Error field_error(const CsvTable& table, std::size_t row, std::string_view column, std::string_view problem) {
  return Error{fmt::format("{}:{}: {}: {}", table.source(), table.line(row), column, problem)};
}

// A measurement: a positive finite number, nothing else in the field.
Result<double> parse_measurement(const CsvTable& table, std::size_t row, std::size_t index, std::string_view column) {
  const std::string& text = table.field(row, index);
  double v = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(v))
    return field_error(table, row, column, fmt::format("\"{}\" is not a number", text));
  if (v <= 0) return field_error(table, row, column, fmt::format("{} is not a positive measurement", text));
  return v;
}

Result<int> subject_id(const CsvTable& table, std::size_t row, std::size_t index) {
  const std::string& text = table.field(row, index);
  int v = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || ptr != end || v <= 0)
    return field_error(table, row, "SubjectId", fmt::format("\"{}\" is not a positive integer", text));
  return v;
}

}  // namespace

std::string_view to_string(Sex sex) { return sex == Sex::Female ? "female" : "male"; }

Result<std::vector<AnsurSubject>> parse_ansur_csv(std::string_view text, std::string_view source) {
  auto table = CsvTable::parse(text, source);
  if (!table) return table.error();
  // Every column is looked up before any row is read, so a release
  // without one fails once, naming it, whatever its rows hold.
  auto id_column = table->column("SubjectId");
  if (!id_column) return id_column.error();
  auto sex_column = table->column("Gender");
  if (!sex_column) return sex_column.error();
  std::vector<std::size_t> indices;
  for (const Column& c : kColumns) {
    auto index = table->column(c.name);
    if (!index) return index.error();
    indices.push_back(*index);
  }

  std::vector<AnsurSubject> out;
  out.reserve(table->rows());
  for (std::size_t row = 0; row < table->rows(); ++row) {
    AnsurSubject s;
    auto id = subject_id(*table, row, *id_column);
    if (!id) return id.error();
    s.id = *id;
    const std::string& sex = table->field(row, *sex_column);
    if (sex == "Male") s.sex = Sex::Male;
    else if (sex == "Female") s.sex = Sex::Female;
    else return field_error(*table, row, "Gender", fmt::format("\"{}\" is not Male or Female", sex));
    for (std::size_t k = 0; k < std::size(kColumns); ++k) {
      auto v = parse_measurement(*table, row, indices[k], kColumns[k].name);
      if (!v) return v.error();
      s.*kColumns[k].field = *v * kColumns[k].scale;
    }
    out.push_back(s);
  }
  if (out.empty()) return Error{fmt::format("{}: no subjects after the header", source)};
  return out;
}

Result<std::vector<AnsurSubject>> read_ansur_csv(const std::filesystem::path& file) {
  auto text = read_text_file(file);
  if (!text) return text.error();
  return parse_ansur_csv(*text, file.string());
}

Result<std::vector<AnsurSubject>> read_ansur(const std::filesystem::path& directory) {
  std::vector<AnsurSubject> all;
  std::unordered_set<int> seen;
  for (const char* name : {"ANSUR_II_MALE_Public.csv", "ANSUR_II_FEMALE_Public.csv"}) {
    const std::filesystem::path file = directory / name;
    auto subjects = read_ansur_csv(file);
    if (!subjects) return subjects.error();
    for (const AnsurSubject& s : *subjects) {
      if (!seen.insert(s.id).second)
        return Error{fmt::format("{}: SubjectId {} appears twice in the release", file.string(), s.id)};
      all.push_back(s);
    }
  }
  return all;
}

std::optional<double> measurement(const AnsurSubject& s, std::string_view column) {
  for (const Column& c : kColumns)
    if (column == c.name) return s.*c.field;
  return std::nullopt;
}

Result<AnsurSubject> find_subject(const std::vector<AnsurSubject>& subjects, int id) {
  for (const AnsurSubject& s : subjects)
    if (s.id == id) return s;
  return Error{fmt::format("ANSUR II: no subject with SubjectId {}", id)};
}

}  // namespace spinewatch::anthropometry
