// The commands a client may send (docs/protocol.md, "Commands"): each
// line is one command or one clear error naming the field.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "ops/client_command.hpp"

namespace spinewatch {
namespace {

TEST(ClientCommand, SetWorkerWithStatureMassOrNeither) {
  auto both = parse_client_command(R"({"command": "set_worker", "stature_mm": 1755, "mass_kg": 81.5})");
  ASSERT_TRUE(both) << both.error().message;
  EXPECT_EQ(both->worker, (KnownWorker{1755.0, 81.5}));

  auto stature = parse_client_command(R"({"command":"set_worker","stature_mm":1600,"mass_kg":null})");
  ASSERT_TRUE(stature) << stature.error().message;
  EXPECT_EQ(stature->worker, (KnownWorker{1600.0, std::nullopt}));

  auto unknown = parse_client_command(R"({"command":"set_worker"})");
  ASSERT_TRUE(unknown) << unknown.error().message;
  EXPECT_EQ(unknown->worker, KnownWorker{}) << "an unknown worker: everything measured or estimated";
  EXPECT_FALSE(unknown->id);

  auto named = parse_client_command(R"({"command":"set_worker","id":"w-17.b_2","mass_kg":70})");
  ASSERT_TRUE(named) << named.error().message;
  EXPECT_EQ(named->id, "w-17.b_2");
}

TEST(ClientCommand, SetWorkerWithMeasuredLandmarks) {
  auto all = parse_client_command(
      R"({"command":"set_worker","stature_mm":1755,"c7_height_mm":1500,"iliac_crest_height_mm":1040})");
  ASSERT_TRUE(all) << all.error().message;
  EXPECT_EQ(all->worker, (KnownWorker{1755.0, std::nullopt, 1500.0, 1040.0}));
  const auto reply = nlohmann::json::parse(accepted_reply(*all));
  EXPECT_EQ(reply.at("worker").at("c7_height_mm"), 1500.0);
  EXPECT_EQ(reply.at("worker").at("iliac_crest_height_mm"), 1040.0);
  const auto plain = nlohmann::json::parse(accepted_reply({KnownWorker{1755.0, std::nullopt}, std::nullopt}));
  EXPECT_FALSE(plain.at("worker").contains("c7_height_mm")) << "landmarks only when given";
}

TEST(ClientCommand, BadLinesSayWhatIsWrong) {
  const std::pair<const char*, const char*> cases[] = {
      {"hello", "not valid JSON (one JSON object per line)"},
      {R"({"command": "set_worker", "stature_mm": 1e309})", "not valid JSON (one JSON object per line)"},
      {"[1, 2]", "not a JSON object"},
      {R"({"stature_mm": 1700})", "command: missing"},
      {R"({"command": 7})", "command: expected a string, got number"},
      {R"({"command": "shutdown"})", "command: \"shutdown\" is not a command (known: set_worker)"},
      {R"({"command": "set_worker", "height": 1700})",
       "height: not a field of set_worker (stature_mm, mass_kg, c7_height_mm, iliac_crest_height_mm, id)"},
      {R"({"command": "set_worker", "c7_height_mm": 150})", "c7_height_mm: 150 is out of range [800, 2000]"},
      {R"({"command": "set_worker", "stature_mm": 1600, "c7_height_mm": 1550})",
       "c7_height_mm: 1550 mm is not at least 100 mm below the stature (1600 mm)"},
      {R"({"command": "set_worker", "id": 17})", "id: expected a string or null, got number"},
      {R"({"command": "set_worker", "id": "w 17"})", "id: 1 to 64 letters, digits, '.', '_' or '-'"},
      {R"({"command": "set_worker", "id": ""})", "id: 1 to 64 letters, digits, '.', '_' or '-'"},
      {R"({"command": "set_worker", "stature_mm": "tall"})", "stature_mm: expected a number or null, got string"},
      {R"({"command": "set_worker", "stature_mm": 400})", "stature_mm: 400 is out of range [1000, 2300]"},
      {R"({"command": "set_worker", "mass_kg": 300})", "mass_kg: 300 is out of range [20, 250]"},
  };
  for (const auto& [line, message] : cases) {
    auto r = parse_client_command(line);
    ASSERT_FALSE(r) << line;
    EXPECT_EQ(r.error().message, message) << line;
  }
}

// Found by the client_command fuzzer: a client's string with a line end
// in it went into the message, and so into the daemon's log as a line of
// the client's making.
TEST(ClientCommand, WhatAClientSentCannotForgeALogLine) {
  auto command = parse_client_command(R"({"command": "x\n2026-12-02 info: forged"})");
  ASSERT_FALSE(command);
  EXPECT_EQ(command.error().message, R"(command: "x\n2026-12-02 info: forged" is not a command (known: set_worker))");
  auto key = parse_client_command(R"({"command": "set_worker", "a\u001bb": 1})");
  ASSERT_FALSE(key);
  EXPECT_EQ(key.error().message, R"(a\x1bb: not a field of set_worker (stature_mm, mass_kg, c7_height_mm, iliac_crest_height_mm, id))");
}

TEST(ClientCommand, RepliesAreReplyLines) {
  const auto ok = nlohmann::json::parse(accepted_reply({KnownWorker{1755.0, std::nullopt}, std::nullopt}));
  EXPECT_EQ(ok.at("class"), "reply");
  EXPECT_EQ(ok.at("v"), 1);
  EXPECT_EQ(ok.at("command"), "set_worker");
  EXPECT_EQ(ok.at("ok"), true);
  EXPECT_EQ(ok.at("worker").at("stature_mm"), 1755.0);
  EXPECT_TRUE(ok.at("worker").at("mass_kg").is_null());
  EXPECT_FALSE(ok.at("worker").contains("id"));
  const auto with_id = nlohmann::json::parse(accepted_reply({KnownWorker{}, "w-17"}));
  EXPECT_EQ(with_id.at("worker").at("id"), "w-17");

  const auto bad = nlohmann::json::parse(rejected_reply(Error{"command: missing"}));
  EXPECT_EQ(bad.at("class"), "reply");
  EXPECT_EQ(bad.at("ok"), false);
  EXPECT_EQ(bad.at("error"), "command: missing");
  EXPECT_FALSE(bad.contains("command"));
}

}  // namespace
}  // namespace spinewatch
