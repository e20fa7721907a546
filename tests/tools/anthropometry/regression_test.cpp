#include <gtest/gtest.h>

#include <string>

#include "spinewatch/estimator/anatomy/linear_regression.hpp"

namespace spinewatch {
namespace {

const char* const kModel = R"(
[[regression]]
target = "cervicaleheight"
inputs = ["stature", "acromialheight"]
intercept = 10.0
coefficients = [0.5, 0.25]
residual_sd = 12.0

[[regression]]
target = "cervicaleheight"
inputs = ["stature", "male"]
intercept = -5.0
coefficients = [0.86, 8.0]
residual_sd = 11.0
)";

TEST(LinearRegression, PredictsByPositionAndByName) {
  auto model = parse_anthropometry(kModel, "a.toml");
  ASSERT_TRUE(model) << model.error().message;
  const LinearRegression* plain = model->find("cervicaleheight", false);
  const LinearRegression* sexed = model->find("cervicaleheight", true);
  ASSERT_NE(plain, nullptr);
  ASSERT_NE(sexed, nullptr);
  EXPECT_EQ(model->find("iliocristaleheight", false), nullptr);
  const double x[] = {1700, 1400};
  EXPECT_DOUBLE_EQ(plain->predict(x), 10 + 850 + 350);
  auto by_name = plain->predict({{"stature", 1700}, {"acromialheight", 1400}, {"unused", 3}});
  ASSERT_TRUE(by_name) << by_name.error().message;
  EXPECT_DOUBLE_EQ(*by_name, 1210);
  EXPECT_DOUBLE_EQ(*sexed->predict({{"stature", 1700}, {"male", 1}}), -5 + 0.86 * 1700 + 8);
  auto missing = plain->predict({{"stature", 1700}});
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, "cervicaleheight: input acromialheight not given");
  EXPECT_DOUBLE_EQ(plain->residual_sd, 12);
}

TEST(LinearRegression, BadFilesNameTheProblem) {
  struct Case {
    std::string from, to;
    const char* expected;
  };
  const Case cases[] = {
      {"coefficients = [0.5, 0.25]", "coefficients = [0.5]", "regression[0]: 2 inputs but 1 coefficients"},
      {"intercept = 10.0", "intercep = 10.0", "regression[0].intercept: missing"},
      {"coefficients = [0.5, 0.25]", "coefficients = [0.5, \"x\"]", "regression[0].coefficients: expected finite numbers"},
      {"target = \"cervicaleheight\"\ninputs = [\"stature\", \"male\"]", "target = \"cervicaleheight\"\ninputs = [\"stature\", \"acromialheight\"]",
       "regression[1]: a second model of cervicaleheight without sex"},
  };
  for (const Case& c : cases) {
    std::string text = kModel;
    const auto at = text.find(c.from);
    ASSERT_NE(at, std::string::npos) << c.from;
    text.replace(at, c.from.size(), c.to);
    auto r = parse_anthropometry(text, "a.toml");
    ASSERT_FALSE(r.ok()) << c.expected;
    EXPECT_NE(r.error().message.find(c.expected), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.rfind("a.toml", 0), 0u) << r.error().message;
  }
  auto none = parse_anthropometry("[source]\ndataset = \"ANSUR II\"\n", "a.toml");
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.error().message, "a.toml: [[regression]]: missing");
}

}  // namespace
}  // namespace spinewatch
