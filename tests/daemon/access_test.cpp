// The access pieces on their own: token files, the auth line, refusal
// log limiting, pseudonyms, the Unix socket's group.
#include <gtest/gtest.h>

#include <grp.h>
#include <sys/stat.h>
#include <unistd.h>

#include <spdlog/spdlog.h>

#include "access/access.hpp"
#include "access/pseudonym.hpp"
#include "net/unix_listener.hpp"
#include "publish/publisher.hpp"
#include "spinewatch/daemon/config.hpp"
#include "test_client.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;

TEST(Tokens, NamedAndBareTokensMatchExactlyAndNothingElseDoes) {
  const auto set = TokenSet::from_lines("# comment\n\nops: alpha-token \nbravo-token\r\nscraper:charlie\n");
  EXPECT_EQ(set.size(), 3u);
  EXPECT_EQ(set.match("alpha-token"), "ops");
  EXPECT_EQ(set.match("bravo-token"), "token 4");  // named by its line: the log never shows a token
  EXPECT_EQ(set.match("charlie"), "scraper");
  for (const char* wrong : {"", "alpha-toke", "alpha-token ", "ALPHA-TOKEN", "ops", "ops:alpha-token", "charliex"})
    EXPECT_FALSE(set.match(wrong)) << wrong;
}

TEST(Tokens, AFileOthersCanReadOrWithoutATokenIsRefused) {
  test::TempDir dir;
  const auto path = dir / "tokens";
  test::write_file(path, "a:secret-1\n");
  ::chmod(path.c_str(), 0640);
  auto loaded = TokenSet::load(path, "publish.token_file");
  ASSERT_FALSE(loaded);
  EXPECT_EQ(loaded.error().message, "publish.token_file " + path.string() +
                                        ": mode 0640 lets other users read a secret; chmod 600 " + path.string() +
                                        " (0600 or stricter)");
  ::chmod(path.c_str(), 0400);
  EXPECT_TRUE(TokenSet::load(path, "publish.token_file"));
  ::chmod(path.c_str(), 0600);
  test::write_file(path, "# nothing\n\n");
  loaded = TokenSet::load(path, "http.token_file");
  ASSERT_FALSE(loaded);
  EXPECT_NE(loaded.error().message.find("http.token_file " + path.string() + ": no token in it"), std::string::npos);
  EXPECT_FALSE(TokenSet::load(dir / "absent", "http.token_file"));
}

TEST(Tokens, TheAuthLineIsOneJsonObjectWithAStringToken) {
  EXPECT_EQ(auth_token_of(R"({"command":"auth","token":"t-1"})"), "t-1");
  EXPECT_EQ(auth_token_of(R"({"token":"t-1","command":"auth"})"), "t-1");
  for (const char* not_auth : {"", "auth t-1", R"({"command":"auth"})", R"({"command":"auth","token":17})",
                               R"({"command":"set_worker","token":"t-1"})", R"(["auth","t-1"])", R"({"command":"auth","token":"t-1")"})
    EXPECT_FALSE(auth_token_of(not_auth)) << not_auth;
}

TEST(Access, TlsNeedsCertificateAndKeyAndTheNetworkNeedsAnAuthentication) {
  auto none = load_access({}, "publish");
  ASSERT_TRUE(none);
  EXPECT_FALSE(none->safe_for_network());
  EXPECT_EQ(none->describe(), "no TLS, no authentication");
  auto half = load_access({"/x/cert.pem", "", "", ""}, "http");
  ASSERT_FALSE(half);
  EXPECT_EQ(half.error().message, "http.tls_cert: set, but http.tls_key is not: TLS needs the certificate and its key");
  auto ca_only = load_access({"", "", "/x/ca.pem", ""}, "publish");
  ASSERT_FALSE(ca_only);
  EXPECT_NE(ca_only.error().message.find("publish.tls_client_ca: client certificates need TLS"), std::string::npos);
  test::TempDir dir;
  test::write_file(dir / "tokens", "t\n");
  ::chmod((dir / "tokens").c_str(), 0600);
  auto tokens_only = load_access({"", "", "", (dir / "tokens").string()}, "publish");
  ASSERT_TRUE(tokens_only);
  EXPECT_TRUE(tokens_only->authenticates());
  EXPECT_FALSE(tokens_only->safe_for_network()) << "tokens in clear";
  EXPECT_EQ(tokens_only->describe(), "1 token");
}

TEST(LogLimiter, OneLinePerPeriodCountingTheOnesHeldBack) {
  LogLimiter limiter(10s);
  const auto t0 = std::chrono::steady_clock::time_point{} + 100s;
  EXPECT_EQ(limiter.admit(t0), 0u);
  EXPECT_FALSE(limiter.admit(t0 + 1s));
  EXPECT_FALSE(limiter.admit(t0 + 9s));
  EXPECT_EQ(limiter.admit(t0 + 10s), 2u);
  EXPECT_EQ(limiter.admit(t0 + 30s), 0u);
}

TEST(Pseudonyms, MadeOnceStableAndKeyedByTheStationSecret) {
  test::TempDir dir;
  const auto secret = dir / "pseudonym.key";
  auto a = Pseudonyms::open(secret);
  ASSERT_TRUE(a) << a.error().message;
  struct stat st {};
  ASSERT_EQ(::stat(secret.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  const std::string p = a->of("w-17");
  EXPECT_TRUE(p.size() == 14 && p.rfind("w-", 0) == 0 && p.find_first_not_of("0123456789abcdef", 2) == std::string::npos) << p;
  EXPECT_NE(a->of("w-18"), p);
  EXPECT_EQ(Pseudonyms::open(secret)->of("w-17"), p) << "a second open reads the same secret";
  // Known answer: HMAC-SHA256 keyed with the file's 64 hex digits as text.
  test::write_file(secret, std::string(64, 'a') + "\n");
  EXPECT_EQ(Pseudonyms::open(secret)->of("w-17"),
            "w-" + test::run_command("printf %s w-17 | openssl dgst -sha256 -hmac " + std::string(64, 'a') +
                                     " | sed 's/.*= //'").output.substr(0, 12));
  EXPECT_NE(Pseudonyms::open(secret)->of("w-17"), p);
  test::write_file(secret, "not hex\n");
  auto bad = Pseudonyms::open(secret);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("expected 64 lower-case hex digits"), std::string::npos);
  ::chmod(secret.c_str(), 0644);
  bad = Pseudonyms::open(secret);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("privacy.secret_file " + secret.string() + ": mode 0644"), std::string::npos);
}

TEST(UnixSocketGroup, TheOwnPrimaryGroupIsGivenTheSocketAnUnknownOneRefused) {
  const group* own = ::getgrgid(::getgid());
  ASSERT_NE(own, nullptr);
  const std::string name = own->gr_name;
  auto gid = group_id(name, "publish.unix_socket_group");
  ASSERT_TRUE(gid) << gid.error().message;
  EXPECT_EQ(*gid, ::getgid());
  auto unknown = group_id("no-such-group-sw", "publish.unix_socket_group");
  ASSERT_FALSE(unknown);
  EXPECT_EQ(unknown.error().message,
            "publish.unix_socket_group: no group \"no-such-group-sw\" on this machine (getent group no-such-group-sw)");

  test::TempDir dir;
  spdlog::set_level(spdlog::level::warn);
  PublisherOptions o;
  o.unix_socket = dir / "p.sock";
  o.unix_socket_gid = *gid;
  auto pub = Publisher::start(o, R"({"class":"hello","v":1})");
  spdlog::set_level(spdlog::level::info);
  ASSERT_TRUE(pub) << pub.error().message;
  struct stat st {};
  ASSERT_EQ(::stat((dir / "p.sock").c_str(), &st), 0);
  EXPECT_EQ(st.st_gid, *gid);
  EXPECT_EQ(st.st_mode & 0777, 0660u);
  auto client = test::LineClient::unix_socket(dir / "p.sock");
  EXPECT_EQ(client.read_line(), R"({"class":"hello","v":1})");
}

TEST(AccessConfig, TheKeysAreTakenAndBadValuesNamedWithTheirLine) {
  auto c = parse_config("[publish]\ntls_cert = \"/c.pem\"\ntls_key = \"/k.pem\"\ntls_client_ca = \"/ca.pem\"\n"
                        "token_file = \"/t\"\nauth_timeout_s = 2.5\nunix_socket_group = \"readers\"\n"
                        "[http]\ntls_cert = \"/hc.pem\"\ntoken_file = \"/ht\"\n[privacy]\npseudonymise = false\n"
                        "secret_file = \"/s.key\"\n",
                        "t.toml");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(c->publish.tls_cert, "/c.pem");
  EXPECT_EQ(c->publish.tls_key, "/k.pem");
  EXPECT_EQ(c->publish.tls_client_ca, "/ca.pem");
  EXPECT_EQ(c->publish.token_file, "/t");
  EXPECT_EQ(c->publish.auth_timeout_s, 2.5);
  EXPECT_EQ(c->publish.unix_socket_group, "readers");
  EXPECT_EQ(c->http.tls_cert, "/hc.pem");
  EXPECT_EQ(c->http.token_file, "/ht");
  EXPECT_FALSE(c->privacy.pseudonymise);
  EXPECT_EQ(c->privacy.secret_file, "/s.key");
  EXPECT_EQ(parse_config("[privacy]\npseudonymise = \"yes\"\n", "t.toml").error().message,
            "t.toml:2: privacy.pseudonymise: expected true or false, got string");
  EXPECT_EQ(parse_config("[publish]\n\nauth_timeout_s = 0\n", "t.toml").error().message,
            "t.toml:3: publish.auth_timeout_s: 0 is out of range [0.1, 300]");
  EXPECT_EQ(parse_config("[http]\ntoken_file = 7\n", "t.toml").error().message,
            "t.toml:2: http.token_file: expected a string, got integer");
}

}  // namespace
}  // namespace spinewatch
