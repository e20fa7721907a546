#include <gtest/gtest.h>
#include <sys/stat.h>

#include <atomic>
#include <future>
#include <thread>

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "net/unix_listener.hpp"
#include "publish/publisher.hpp"
#include "support/station_dirs.hpp"
#include "test_client.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;
using test::LineClient;
using test::eventually;

const std::string kHello = R"({"class":"hello","v":1,"daemon_version":"test","station":"bench"})";

std::string numbered(std::uint64_t i, std::size_t pad = 0) {
  return nlohmann::json{{"class", "posture"}, {"seq", i}, {"pad", std::string(pad, 'x')}}.dump();
}
std::uint64_t seq_of(const std::string& line) { return nlohmann::json::parse(line).at("seq").get<std::uint64_t>(); }

class PublisherTest : public ::testing::Test {
 protected:
  void SetUp() override { spdlog::set_level(spdlog::level::warn); }
  void TearDown() override { spdlog::set_level(spdlog::level::info); }

  std::unique_ptr<Publisher> start(PublisherOptions options) {
    auto p = Publisher::start(options, kHello);
    if (!p) ADD_FAILURE() << p.error().message;
    return p ? std::move(p).value() : nullptr;
  }
  PublisherOptions both() {
    PublisherOptions o;
    o.tcp = TcpEndpoint{"127.0.0.1", 0};
    o.unix_socket = dir.path() / "p.sock";
    return o;
  }
  test::TempDir dir;
};

TEST_F(PublisherTest, HelloFirstThenLinesOnTcpAndUnix) {
  auto pub = start(both());
  ASSERT_TRUE(pub);
  ASSERT_NE(pub->tcp_port(), 0);
  struct stat st{};
  ASSERT_EQ(::stat((dir.path() / "p.sock").c_str(), &st), 0);
  EXPECT_TRUE(S_ISSOCK(st.st_mode));
  EXPECT_EQ(st.st_mode & 0777, 0660u);

  auto tcp = LineClient::tcp(pub->tcp_port());
  auto local = LineClient::unix_socket(dir.path() / "p.sock");
  EXPECT_EQ(tcp.read_line(), kHello);
  EXPECT_EQ(local.read_line(), kHello);
  pub->publish(numbered(7));
  EXPECT_EQ(tcp.read_line(), numbered(7));
  EXPECT_EQ(local.read_line(), numbered(7));
  EXPECT_EQ(pub->stats().clients, 2u);
}

TEST_F(PublisherTest, NewHelloForLaterClients) {
  auto pub = start(both());
  ASSERT_TRUE(pub);
  const std::string renamed = R"({"class":"hello","v":1,"daemon_version":"test","station":"renamed"})";
  pub->set_hello(renamed);
  auto c = LineClient::tcp(pub->tcp_port());
  EXPECT_EQ(c.read_line(), renamed);
}

TEST_F(PublisherTest, TwoReadersGetEveryLineInOrder) {
  auto options = both();
  options.client_queue = 100000;  // this test is about order, not drops: readers may be descheduled
  options.inbox = 100000;
  auto pub = start(options);
  ASSERT_TRUE(pub);
  auto a = LineClient::tcp(pub->tcp_port());
  auto b = LineClient::unix_socket(dir.path() / "p.sock");
  ASSERT_EQ(a.read_line(), kHello);
  ASSERT_EQ(b.read_line(), kHello);
  constexpr std::uint64_t kLines = 2000;
  std::vector<std::uint64_t> got_a, got_b;
  std::thread reader_a([&] {
    while (got_a.size() < kLines)
      if (auto l = a.read_line()) got_a.push_back(seq_of(*l)); else break;
  });
  std::thread reader_b([&] {
    while (got_b.size() < kLines)
      if (auto l = b.read_line()) got_b.push_back(seq_of(*l)); else break;
  });
  for (std::uint64_t i = 0; i < kLines; ++i) {
    pub->publish(numbered(i, 200));
    if (i % 50 == 0) std::this_thread::sleep_for(1ms);  // a camera's pace, roughly
  }
  reader_a.join();
  reader_b.join();
  ASSERT_EQ(got_a.size(), kLines);
  ASSERT_EQ(got_b.size(), kLines);
  for (std::uint64_t i = 0; i < kLines; ++i) {
    ASSERT_EQ(got_a[i], i);
    ASSERT_EQ(got_b[i], i);
  }
  EXPECT_EQ(pub->stats().clients_dropped, 0u);
  EXPECT_EQ(pub->stats().lines, kLines);
}

// publish() hands a line to the I/O thread and returns: it never waits for
// that thread, so it cannot wait for a client. Shown by construction, not
// by a stopwatch: with the I/O thread held, publishing more lines than the
// inbox holds still returns, and the overflow is counted, not waited out.
TEST_F(PublisherTest, PublishReturnsWhileTheIoThreadIsHeld) {
  auto options = both();
  options.inbox = 64;
  auto pub = start(options);
  ASSERT_TRUE(pub);
  std::promise<void> release;
  std::promise<void> held;
  boost::asio::post(pub->io_context(), [&] {
    held.set_value();
    release.get_future().wait();
  });
  held.get_future().wait();
  for (std::uint64_t i = 0; i < 1000; ++i) pub->publish(numbered(i, 1000));
  const auto held_stats = pub->stats();
  release.set_value();
  EXPECT_EQ(held_stats.lines, 0u) << "the held I/O thread sent lines";
  EXPECT_EQ(held_stats.inbox, 64u);
  EXPECT_EQ(held_stats.lines_dropped, 1000u - 64u);
  EXPECT_TRUE(eventually([&] { return pub->stats().lines == 64u; })) << pub->stats().lines;
}

TEST_F(PublisherTest, SilentClientIsDroppedWithoutDelayingTheOthers) {
  auto options = both();
  options.client_queue = 256;
  options.send_buffer_bytes = 4096;
  // Every line reaches the I/O thread, however the test's threads are
  // scheduled on a loaded machine: this test is about the clients' queues.
  options.inbox = 100000;
  auto pub = start(options);
  ASSERT_TRUE(pub);
  auto silent = LineClient::tcp(pub->tcp_port(), 4096);  // never reads
  auto reader = LineClient::unix_socket(dir.path() / "p.sock");
  ASSERT_EQ(reader.read_line(), kHello);
  ASSERT_TRUE(eventually([&] { return pub->stats().clients == 2; }));

  // The publishing is paced by the reader: it never lags more than half its
  // queue behind, however the threads are scheduled, while the silent
  // client's queue fills up and it is dropped.
  constexpr std::uint64_t kLines = 1500;
  constexpr std::uint64_t kMaxLag = 128;
  std::vector<std::uint64_t> got;
  std::atomic<std::uint64_t> received{0};
  std::atomic<bool> reader_done{false};
  std::thread read_all([&] {
    while (got.size() < kLines) {
      if (auto l = reader.read_line()) got.push_back(seq_of(*l)); else break;
      received.store(got.size());
    }
    reader_done.store(true);
  });
  for (std::uint64_t i = 0; i < kLines; ++i) {
    while (i >= received.load() + kMaxLag && !reader_done.load()) std::this_thread::sleep_for(100us);
    pub->publish(numbered(i, 1000));
  }
  read_all.join();

  ASSERT_EQ(got.size(), kLines) << "the reading client lost lines";
  for (std::uint64_t i = 0; i < kLines; ++i) ASSERT_EQ(got[i], i);
  EXPECT_EQ(pub->stats().clients_dropped, 1u);
  EXPECT_TRUE(eventually([&] { return pub->stats().clients == 1u; })) << pub->stats().clients;
  EXPECT_TRUE(silent.wait_closed(5s)) << "the silent client was not disconnected";
}

TEST_F(PublisherTest, ClientInputIsIgnoredAndFloodersAreDropped) {
  auto pub = start(both());
  ASSERT_TRUE(pub);
  auto chatty = LineClient::tcp(pub->tcp_port());
  auto flooder = LineClient::unix_socket(dir.path() / "p.sock");
  auto reader = LineClient::tcp(pub->tcp_port());
  ASSERT_EQ(chatty.read_line(), kHello);
  ASSERT_EQ(flooder.read_line(), kHello);
  ASSERT_EQ(reader.read_line(), kHello);

  ASSERT_TRUE(chatty.send_text("{\"cmd\":\"shutdown\"}\n\x01\x02garbage\n"));
  std::string flood(64 * 1024, 'z');
  flooder.send_text(flood);  // may fail part-way once the daemon has hung up
  ASSERT_TRUE(eventually([&] { return pub->stats().clients_dropped == 1; }));

  for (std::uint64_t i = 0; i < 10; ++i) pub->publish(numbered(i));
  for (std::uint64_t i = 0; i < 10; ++i) {
    EXPECT_EQ(reader.read_line(), numbered(i));
    EXPECT_EQ(chatty.read_line(), numbered(i)) << "a little input must not change anything";
  }
  EXPECT_TRUE(flooder.wait_closed(5s));
  EXPECT_TRUE(eventually([&] { return pub->stats().clients == 2u; })) << pub->stats().clients;
}

// With a command handler: each line a client sends is answered to that
// client alone, in order with its stream; accepted commands do not count
// against the input allowance, other lines do.
TEST_F(PublisherTest, CommandsAreAnsweredToTheirSenderAlone) {
  auto options = both();
  options.max_input_bytes = 200;
  std::atomic<int> lines{0};
  options.on_input = [&](std::string_view line, const std::string& client) {
    ++lines;
    const bool ok = line.rfind("ok", 0) == 0;
    return ClientInputReply{"{\"reply\":\"" + std::string(line) + "\",\"from\":\"" + client + "\"}", ok};
  };
  auto pub = start(options);
  ASSERT_TRUE(pub);
  auto sender = LineClient::unix_socket(dir.path() / "p.sock");
  auto other = LineClient::tcp(pub->tcp_port());
  ASSERT_EQ(sender.read_line(), kHello);
  ASSERT_EQ(other.read_line(), kHello);

  pub->publish(numbered(1));
  ASSERT_EQ(sender.read_line(), numbered(1));
  ASSERT_TRUE(sender.send_text("ok one\r\nok tw"));
  ASSERT_TRUE(sender.send_text("o\n"));
  auto first = sender.read_line();
  ASSERT_TRUE(first);
  EXPECT_EQ(nlohmann::json::parse(*first).at("reply"), "ok one") << "the carriage return is not part of the line";
  EXPECT_NE(nlohmann::json::parse(*first).at("from").get<std::string>().find("unix"), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(*sender.read_line()).at("reply"), "ok two") << "a line split over two reads";
  pub->publish(numbered(2));
  EXPECT_EQ(sender.read_line(), numbered(2));
  EXPECT_EQ(other.read_line(), numbered(1));
  EXPECT_EQ(other.read_line(), numbered(2)) << "the other client gets no reply";

  // 30 accepted commands (300 bytes) stay within an allowance of 200 bytes
  // for what is not a command ...
  for (int i = 0; i < 30; ++i) ASSERT_TRUE(sender.send_text("ok " + std::to_string(i % 10) + "...\n"));
  ASSERT_TRUE(eventually([&] { return lines == 32; }));
  for (int i = 0; i < 30; ++i) ASSERT_TRUE(sender.read_line());
  EXPECT_EQ(pub->stats().clients_dropped, 0u);
  // ... which lines that are not commands use up.
  for (int i = 0; i < 25; ++i) sender.send_text("nonsense\n");
  ASSERT_TRUE(eventually([&] { return pub->stats().clients_dropped == 1; }));
  EXPECT_TRUE(sender.wait_closed(5s));
  // The drop is counted before the session is removed: the count of
  // clients follows a moment later (seen under ASan: 2 right after).
  EXPECT_TRUE(eventually([&] { return pub->stats().clients == 1u; })) << pub->stats().clients;
}

// Unfinished (no newline yet) or whole: a line over 512 bytes is not a
// command, and the handler never sees it.
TEST_F(PublisherTest, ALineLongerThanACommandDropsTheClient) {
  auto options = both();
  std::atomic<int> handled{0};
  options.on_input = [&](std::string_view, const std::string&) {
    ++handled;
    return ClientInputReply{};
  };
  auto pub = start(options);
  ASSERT_TRUE(pub);
  auto unfinished = LineClient::tcp(pub->tcp_port());
  auto whole = LineClient::unix_socket(dir.path() / "p.sock");
  ASSERT_EQ(unfinished.read_line(), kHello);
  ASSERT_EQ(whole.read_line(), kHello);
  ASSERT_TRUE(unfinished.send_text(std::string(513, 'x')));
  ASSERT_TRUE(whole.send_text(std::string(600, 'y') + "\n"));
  ASSERT_TRUE(eventually([&] { return pub->stats().clients_dropped == 2; }));
  EXPECT_TRUE(unfinished.wait_closed(5s));
  EXPECT_TRUE(whole.wait_closed(5s));
  EXPECT_EQ(handled, 0);
}

TEST_F(PublisherTest, ManyConnectsAndDisconnectsLeakNoDescriptors) {
  auto pub = start(both());
  ASSERT_TRUE(pub);
  { auto warm = LineClient::tcp(pub->tcp_port()); ASSERT_TRUE(warm.read_line()); }
  ASSERT_TRUE(eventually([&] { return pub->stats().clients == 0; }));
  const int before = test::open_fd_count();
  for (int i = 0; i < 150; ++i) {
    auto t = LineClient::tcp(pub->tcp_port());
    auto u = LineClient::unix_socket(dir.path() / "p.sock");
    if (i % 2 == 0) {  // half of them go before reading anything
      ASSERT_TRUE(t.read_line());
      ASSERT_TRUE(u.read_line());
    }
    if (i % 10 == 0) pub->publish(numbered(static_cast<std::uint64_t>(i)));
  }
  // Every connection accepted (the last ones' accept handlers may still be
  // queued when the clients are already gone: their descriptors are open
  // but not yet counted) and closed again.
  ASSERT_TRUE(eventually([&] { return pub->stats().clients_total == 301u && pub->stats().clients == 0; }))
      << pub->stats().clients_total << " accepted, " << pub->stats().clients << " clients left";
  EXPECT_TRUE(eventually([&] { return test::open_fd_count() == before; })) << test::open_fd_count() << " descriptors, " << before << " before";
  EXPECT_EQ(pub->stats().clients_total, 301u);
  EXPECT_EQ(pub->stats().clients_dropped, 0u);
}

TEST_F(PublisherTest, MaxClientsRefusesTheRest) {
  auto options = both();
  options.max_clients = 2;
  auto pub = start(options);
  ASSERT_TRUE(pub);
  auto a = LineClient::tcp(pub->tcp_port());
  auto b = LineClient::unix_socket(dir.path() / "p.sock");
  ASSERT_TRUE(a.read_line());
  ASSERT_TRUE(b.read_line());
  auto c = LineClient::tcp(pub->tcp_port());
  EXPECT_FALSE(c.read_line(2s));
  EXPECT_TRUE(c.saw_eof());
  EXPECT_EQ(pub->stats().clients_rejected, 1u);
  EXPECT_EQ(pub->stats().clients, 2u);
}

TEST_F(PublisherTest, StaleSocketFileIsReplacedButALiveOneIsNot) {
  const auto path = dir.path() / "p.sock";
  {
    PublisherOptions o;
    o.unix_socket = path;
    auto first = start(o);
    ASSERT_TRUE(first);
    auto second = Publisher::start(o, kHello);  // the first is still listening
    ASSERT_FALSE(second.ok());
    EXPECT_NE(second.error().message.find("another process is listening"), std::string::npos) << second.error().message;
    ASSERT_TRUE(std::filesystem::exists(path)) << "a failed start removed a live socket";
  }
  EXPECT_FALSE(std::filesystem::exists(path)) << "stop() leaves the socket file";

  // A socket file nobody listens on (a daemon that was killed).
  int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  std::strncpy(a.sun_path, path.c_str(), sizeof a.sun_path - 1);
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  ::close(fd);
  ASSERT_TRUE(std::filesystem::is_socket(path));
  PublisherOptions o;
  o.unix_socket = path;
  auto revived = start(o);
  ASSERT_TRUE(revived);
  auto c = LineClient::unix_socket(path);
  EXPECT_EQ(c.read_line(), kHello);
}

TEST_F(PublisherTest, ARegularFileIsNotReplaced) {
  const auto path = dir.path() / "p.sock";
  test::write_file(path, "precious");
  PublisherOptions o;
  o.unix_socket = path;
  auto p = Publisher::start(o, kHello);
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.error().message, "unix socket " + path.string() + ": exists and is not a socket");
  EXPECT_EQ(test::read_file(path), "precious");
}

TEST_F(PublisherTest, PortInUseIsAClearError) {
  auto first = start(both());
  ASSERT_TRUE(first);
  PublisherOptions o;
  o.tcp = TcpEndpoint{"127.0.0.1", first->tcp_port()};
  auto second = Publisher::start(o, kHello);
  ASSERT_FALSE(second.ok());
  EXPECT_NE(second.error().message.find("cannot bind"), std::string::npos) << second.error().message;
}

TEST_F(PublisherTest, StopSendsWholeLinesThenCloses) {
  auto pub = start(both());
  ASSERT_TRUE(pub);
  auto c = LineClient::tcp(pub->tcp_port());
  ASSERT_EQ(c.read_line(), kHello);
  for (std::uint64_t i = 0; i < 20; ++i) pub->publish(numbered(i, 3000));
  pub->stop();
  for (std::uint64_t i = 0; i < 20; ++i) ASSERT_EQ(c.read_line(), numbered(i, 3000));
  EXPECT_FALSE(c.read_line(2s));
  EXPECT_TRUE(c.saw_eof());
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "p.sock"));
}

TEST(ListenAddress, Parses) {
  auto a = parse_listen_address("127.0.0.1:7117");
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a->host, "127.0.0.1");
  EXPECT_EQ(a->port, 7117);
  auto b = parse_listen_address("[::1]:80");
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(b->host, "::1");
  EXPECT_EQ(b->port, 80);
  EXPECT_FALSE(parse_listen_address("localhost").ok());
  EXPECT_FALSE(parse_listen_address("localhost:http").ok());
  EXPECT_FALSE(parse_listen_address("localhost:70000").ok());
  EXPECT_FALSE(parse_listen_address(":7117").ok());
}

TEST(UnixSocketPath, FollowsRuntimeDirectory) {
  const char* old = std::getenv("RUNTIME_DIRECTORY");
  const std::string saved = old ? old : "";
  ::setenv("RUNTIME_DIRECTORY", "/run/a:/run/b", 1);
  auto path = default_unix_socket_path();
  ASSERT_TRUE(path) << path.error().message;
  EXPECT_EQ(*path, "/run/a/posture.sock");
  if (old) ::setenv("RUNTIME_DIRECTORY", saved.c_str(), 1);
  else ::unsetenv("RUNTIME_DIRECTORY");
}

// Off systemd, a daemon started by hand (docs/daemon.md, "Files a daemon
// started by hand uses"): the system directories when it may write there,
// else its user's XDG directories, else /tmp/spinewatch-UID and ~/.local/state.
TEST(StationDirs, SystemdThenSystemThenTheUsersOwn) {
  DirEnvironment env;
  env.uid = 1000;
  env.home = "/home/w";
  bool system_writable = false;
  env.writable_dir = [&](const std::filesystem::path&) { return system_writable; };
  EXPECT_EQ(runtime_dir(env), "/tmp/spinewatch-1000");
  EXPECT_EQ(state_dir(env), "/home/w/.local/state/spinewatch");
  env.xdg_runtime_dir = "/run/user/1000";
  env.xdg_state_home = "/home/w/state";
  EXPECT_EQ(runtime_dir(env), "/run/user/1000/spinewatch");
  EXPECT_EQ(state_dir(env), "/home/w/state/spinewatch");
  system_writable = true;
  EXPECT_EQ(runtime_dir(env), "/run/spinewatch");
  EXPECT_EQ(state_dir(env), "/var/lib/spinewatch");
  env.runtime_directory = "/run/a:/run/b";
  env.state_directory = "/var/lib/a:/var/lib/b";
  EXPECT_EQ(runtime_dir(env), "/run/a");
  EXPECT_EQ(state_dir(env), "/var/lib/a");
}

TEST(StationDirs, TheUsersFallbackIsMadePrivateAndAForeignOneRefused) {
  test::TempDir dir;
  DirEnvironment env;
  env.xdg_runtime_dir = (dir / "run").string();
  env.writable_dir = [](const std::filesystem::path&) { return false; };
  auto sock = default_station_file(StationDir::Runtime, "posture.sock", "publish.unix_socket", env);
  ASSERT_TRUE(sock) << sock.error().message;
  EXPECT_EQ(*sock, dir / "run" / "spinewatch" / "posture.sock");
  struct stat st {};
  ASSERT_EQ(::stat((dir / "run" / "spinewatch").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0700u);
  // A directory others may write to (as anyone could make /tmp/spinewatch-UID first) is not used.
  ASSERT_EQ(::chmod((dir / "run" / "spinewatch").c_str(), 0777), 0);
  auto refused = default_station_file(StationDir::Runtime, "posture.sock", "publish.unix_socket", env);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("set publish.unix_socket to another path"), std::string::npos)
      << refused.error().message;
}

}  // namespace
}  // namespace spinewatch
