#pragma once
// ANSUR II, the 2012 U.S. Army anthropometric survey (Gordon et al. 2014,
// NATICK/TR-15/007): 6 068 measured adults in two CSV files, one row per
// person (../shared/data/ansur2/README.md). Columns are found by name, so
// a release with other columns or another order reads the same.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::anthropometry {

enum class Sex : std::uint8_t { Male, Female };
std::string_view to_string(Sex sex);

// The columns the station uses. Lengths in mm as measured (standing
// heights from the floor, sitting height from the seat); mass in kg.
struct AnsurSubject {
  int id = 0;  // SubjectId
  Sex sex = Sex::Male;
  double stature_mm = 0;
  double cervicale_height_mm = 0;      // C7 spinous process tip, on the skin
  double suprasternale_height_mm = 0;  // top of the sternum
  double acromial_height_mm = 0;       // shoulder point
  double iliocristale_height_mm = 0;   // top of the iliac crest, on the side
  double trochanterion_height_mm = 0;  // top of the greater trochanter
  double crotch_height_mm = 0;
  double sitting_height_mm = 0;        // vertex above the seat, sitting erect
  double biacromial_breadth_mm = 0;
  double bideltoid_breadth_mm = 0;
  double chest_breadth_mm = 0;
  double waist_breadth_mm = 0;
  double hip_breadth_mm = 0;
  double chest_depth_mm = 0;
  double waist_depth_mm = 0;
  double buttock_depth_mm = 0;
  double neck_circumference_base_mm = 0;
  double head_breadth_mm = 0;
  double head_length_mm = 0;
  double tragion_top_of_head_mm = 0;   // ear (tragion) to the vertex
  double acromion_radiale_length_mm = 0;
  double radiale_stylion_length_mm = 0;
  double hand_length_mm = 0;
  double thigh_circumference_mm = 0;
  double calf_circumference_mm = 0;
  double biceps_circumference_mm = 0;   // bicepscircumferenceflexed
  double forearm_circumference_mm = 0;  // forearmcircumferenceflexed
  double popliteal_height_mm = 0;       // seated: floor to the back of the knee
  double mass_kg = 0;                   // weightkg is in tenths of a kilogram
};

// One ANSUR CSV file's text; `source` names it in errors, which say the
// file, the line and the column: "MALE.csv:17: stature: \"n/a\" is not a number".
Result<std::vector<AnsurSubject>> parse_ansur_csv(std::string_view text, std::string_view source);
Result<std::vector<AnsurSubject>> read_ansur_csv(const std::filesystem::path& file);

// Both files of a release directory (ANSUR_II_MALE_Public.csv, then
// ANSUR_II_FEMALE_Public.csv); a SubjectId present twice is an error.
Result<std::vector<AnsurSubject>> read_ansur(const std::filesystem::path& directory);

// Where the data set lies relative to the repository root (CI checks the
// repository out with ../shared beside it).
inline constexpr std::string_view kAnsurRelativeDir = "../shared/data/ansur2";

// A measurement of `s` by its ANSUR column name ("stature", "weightkg" in
// kg), or nullopt for a column the reader does not keep.
std::optional<double> measurement(const AnsurSubject& s, std::string_view column);

// The subject with this SubjectId, or an error naming the id.
Result<AnsurSubject> find_subject(const std::vector<AnsurSubject>& subjects, int id);

}  // namespace spinewatch::anthropometry
