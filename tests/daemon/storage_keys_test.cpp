// [exposure] and [storage] keys reach what they set, and bad values are
// one message naming key and line (their effects: tests/daemon/store_test,
// tests/e2e/daemon_storage_test, tests/tools/replay/replay_summaries_test).
#include <gtest/gtest.h>

#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/exposure_options.hpp"
#include "storage/store.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

TEST(StorageKeys, DefaultsStoreNothingAndSummariseEveryMinute) {
  auto c = parse_config("", "s.toml");
  ASSERT_TRUE(c);
  EXPECT_EQ(c->storage.path, "");
  EXPECT_EQ(c->storage.posture_every, 30);
  EXPECT_EQ(exposure_options(*c).interval_ns, 60'000'000'000);
  EXPECT_DOUBLE_EQ(store_options(*c).retention_days, 90);
  EXPECT_DOUBLE_EQ(store_options(*c).max_size_mb, 0);
}

TEST(StorageKeys, ValuesReachTheirOptions) {
  auto c = parse_config("[exposure]\ninterval_s = 15\n[storage]\npath = \"/var/lib/spinewatch/s.db\"\nposture_every = 3\n"
                        "retention_days = 7.5\nmax_size_mb = 512\n",
                        "s.toml");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(exposure_options(*c).interval_ns, 15'000'000'000);
  EXPECT_EQ(c->storage.posture_every, 3);
  const StoreOptions o = store_options(*c);
  EXPECT_EQ(o.path, "/var/lib/spinewatch/s.db");
  EXPECT_DOUBLE_EQ(o.retention_days, 7.5);
  EXPECT_DOUBLE_EQ(o.max_size_mb, 512);
}

TEST(StorageKeys, BadValuesNameKeyAndLine) {
  auto zero = parse_config("[exposure]\ninterval_s = 0\n", "s.toml");
  ASSERT_FALSE(zero);
  EXPECT_EQ(zero.error().message, "s.toml:2: exposure.interval_s: 0 is out of range [1, 86400]");
  auto every = parse_config("[storage]\n\nposture_every = 0\n", "s.toml");
  ASSERT_FALSE(every);
  EXPECT_EQ(every.error().message, "s.toml:3: storage.posture_every: 0 is out of range [1, 1000000]");
  auto text = parse_config("[storage]\nretention_days = \"long\"\n", "s.toml");
  ASSERT_FALSE(text);
  EXPECT_EQ(text.error().message, "s.toml:2: storage.retention_days: expected a number, got string");
  auto unknown = parse_config("[storage]\nfile = \"x\"\n", "s.toml");
  ASSERT_FALSE(unknown);
  EXPECT_EQ(unknown.error().message, "s.toml:2: storage.file: unknown key");
}

TEST(AlertKeys, BuiltInByDefaultNoneWhenOffAndAFileWithItsErrors) {
  auto c = parse_config("", "s.toml");
  ASSERT_TRUE(c);
  EXPECT_EQ(load_alert_rules(*c)->size(), builtin_alert_rules().size());
  auto off = parse_config("[alerts]\nenabled = false\n", "s.toml");
  ASSERT_TRUE(off);
  EXPECT_TRUE(load_alert_rules(*off)->empty());
  test::TempDir dir;
  test::write_file(dir / "a.toml", "[[rule]]\nname = \"only\"\ncompression_above_n = 2500\n");
  auto file = parse_config("[alerts]\nrules = \"" + (dir / "a.toml").string() + "\"\n", "s.toml");
  ASSERT_TRUE(file);
  auto rules = load_alert_rules(*file);
  ASSERT_TRUE(rules) << rules.error().message;
  ASSERT_EQ(rules->size(), 1u);
  EXPECT_EQ(rules->at(0).name, "only");
  test::write_file(dir / "a.toml", "[[rule]]\nname = \"only\"\n");
  EXPECT_NE(load_alert_rules(*file).error().message.find("a.toml:1: rule[0]: names no condition"), std::string::npos);
  auto missing = parse_config("[alerts]\nrules = \"/nonexistent/a.toml\"\n", "s.toml");
  EXPECT_EQ(load_alert_rules(*missing).error().message, "alerts.rules: /nonexistent/a.toml: cannot be read");
}

}  // namespace
}  // namespace spinewatch
