#include <gtest/gtest.h>

#include <string>

#include <fmt/format.h>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/anthropometry/csv.hpp"
#include "test_support.hpp"

namespace spinewatch::anthropometry {
namespace {

// Every column the reader keeps, in an order unlike the release's (the
// reader goes by name), plus a survey column it ignores.
const char* const kHeader =
    "Gender,weightkg,stature,SubjectId,cervicaleheight,suprasternaleheight,acromialheight,iliocristaleheight,"
    "trochanterionheight,crotchheight,sittingheight,biacromialbreadth,bideltoidbreadth,chestbreadth,waistbreadth,"
    "hipbreadth,chestdepth,waistdepth,buttockdepth,neckcircumferencebase,headbreadth,headlength,tragiontopofhead,"
    "acromionradialelength,radialestylionlength,handlength,thighcircumference,calfcircumference,"
    "bicepscircumferenceflexed,forearmcircumferenceflexed,poplitealheight,SubjectsBirthLocation";

std::string row(std::string_view gender, std::string_view weight, std::string_view stature, std::string_view id,
                std::string_view birthplace = "Ohio") {
  return fmt::format("{},{},{},{},1535,1449,1467,1071,919,877,928,401,493,291,329,332,259,240,240,436,150,206,140,"
                     "337,273,193,610,373,369,299,437,{}",
                     gender, weight, stature, id, birthplace);
}

TEST(AnsurReader, ReadsColumnsByNameWithUnits) {
  const std::string text = std::string(kHeader) + "\r\n" + row("Male", "815", "1776", "10027", "\"Fort Hood, TX\"") +
                           "\r\n" + row("Female", "657", "1560", "10037") + "\n\n";
  auto subjects = parse_ansur_csv(text, "m.csv");
  ASSERT_TRUE(subjects) << subjects.error().message;
  ASSERT_EQ(subjects->size(), 2u);
  const AnsurSubject& a = (*subjects)[0];
  EXPECT_EQ(a.id, 10027);
  EXPECT_EQ(a.sex, Sex::Male);
  EXPECT_EQ(a.stature_mm, 1776);
  EXPECT_EQ(a.cervicale_height_mm, 1535);
  EXPECT_EQ(a.iliocristale_height_mm, 1071);
  EXPECT_EQ(a.sitting_height_mm, 928);
  EXPECT_EQ(a.buttock_depth_mm, 240);
  EXPECT_EQ(a.popliteal_height_mm, 437);
  EXPECT_DOUBLE_EQ(a.mass_kg, 81.5);  // weightkg is in tenths of a kilogram
  EXPECT_EQ((*subjects)[1].sex, Sex::Female);
  EXPECT_EQ(measurement(a, "waistdepth"), 240);
  EXPECT_FALSE(measurement(a, "Installation").has_value());
}

struct BadCase {
  std::string text;
  const char* expected;
};

TEST(AnsurReader, BadInputNamesFileLineAndColumn) {
  std::string no_crotch = kHeader;
  no_crotch.replace(no_crotch.find("crotchheight"), 12, "crotchheigth");
  const BadCase cases[] = {
      {no_crotch + "\n" + row("Male", "815", "1776", "1"), "f.csv:1: column crotchheight: missing from the header"},
      {std::string(kHeader) + "\n" + row("Male", "815", "1776", "1") + "\n" + row("Male", "815", "17x6", "2"),
       "f.csv:3: stature: \"17x6\" is not a number"},
      {std::string(kHeader) + "\n" + row("Male", "", "1776", "1"), "f.csv:2: weightkg: \"\" is not a number"},
      {std::string(kHeader) + "\n" + row("Male", "815", "-5", "1"), "f.csv:2: stature: -5 is not a positive"},
      {std::string(kHeader) + "\n" + row("Male", "815", "1776", "A1"), "f.csv:2: SubjectId: \"A1\" is not a positive integer"},
      {std::string(kHeader) + "\n" + row("M", "815", "1776", "1"), "f.csv:2: Gender: \"M\" is not Male or Female"},
      {std::string(kHeader) + "\n" + row("Male", "815", "1776", "1") + ",extra", "f.csv:2: 33 fields, the header has 32"},
      {std::string(kHeader) + "\n" + row("Male", "815", "1776", "1", "\"open"), "f.csv:2: a quoted field is not closed"},
      {std::string(kHeader) + "\n", "f.csv: no subjects"},
      {"", "f.csv: empty"},
  };
  for (const BadCase& c : cases) {
    auto r = parse_ansur_csv(c.text, "f.csv");
    ASSERT_FALSE(r.ok()) << c.expected;
    EXPECT_NE(r.error().message.find(c.expected), std::string::npos) << r.error().message;
  }
}

TEST(AnsurReader, MissingDirectoryNamesTheFile) {
  auto r = read_ansur("/nonexistent/ansur");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("/nonexistent/ansur/ANSUR_II_MALE_Public.csv: cannot open"), std::string::npos)
      << r.error().message;
}

TEST(AnsurReader, DuplicateIdAcrossFilesIsAnError) {
  test::TempDir dir;
  test::write_file(dir / "ANSUR_II_MALE_Public.csv", std::string(kHeader) + "\n" + row("Male", "815", "1776", "7"));
  test::write_file(dir / "ANSUR_II_FEMALE_Public.csv", std::string(kHeader) + "\n" + row("Female", "615", "1606", "7"));
  auto r = read_ansur(dir.path());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("SubjectId 7 appears twice"), std::string::npos) << r.error().message;
}

// The real release (../shared/data/ansur2, beside the repository).
TEST(AnsurReader, ReadsTheRelease) {
  auto subjects = read_ansur(test::source_path(std::string(kAnsurRelativeDir)));
  ASSERT_TRUE(subjects) << subjects.error().message;
  std::size_t men = 0, women = 0;
  for (const AnsurSubject& s : *subjects) (s.sex == Sex::Male ? men : women)++;
  EXPECT_EQ(men, 4082u);  // README.md: 4 082 men, 1 986 women
  EXPECT_EQ(women, 1986u);
  // The first man of the male file, as its row reads.
  auto first = find_subject(*subjects, 10027);
  ASSERT_TRUE(first) << first.error().message;
  EXPECT_EQ(first->stature_mm, 1776);
  EXPECT_EQ(first->cervicale_height_mm, 1535);
  EXPECT_EQ(first->iliocristale_height_mm, 1071);
  EXPECT_DOUBLE_EQ(first->mass_kg, 81.5);
  auto none = find_subject(*subjects, 1);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("no subject with SubjectId 1"), std::string::npos);
}

}  // namespace
}  // namespace spinewatch::anthropometry
