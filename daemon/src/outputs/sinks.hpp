#pragma once
// The station's own outputs as PostureSinks (posture_sink.hpp): each an
// adapter around a class with its own job (the stream's publisher, the
// store, MQTT, the alert line, the HTTP server with its live view), which
// stays usable on its own. Listed, in stop order, in app/outputs.cpp.
#include <functional>
#include <memory>
#include <string>

#include "exposure/alert_output.hpp"
#include "http/http_server.hpp"
#include "http/live_view.hpp"
#include "mqtt/mqtt_publisher.hpp"
#include "outputs/posture_sink.hpp"
#include "publish/publisher.hpp"
#include "storage/store.hpp"

namespace spinewatch {

// The posture stream's clients (TCP, Unix socket): every line.
class PublisherSink final : public PostureSink {
 public:
  explicit PublisherSink(std::unique_ptr<Publisher> publisher) : publisher_(std::move(publisher)) {}
  Publisher& publisher() { return *publisher_; }

  std::string_view name() const override { return "publisher"; }
  void on_posture(const PostureEvent& event) override { publisher_->publish(event.line); }
  void on_summary(const SummaryLine& summary, const std::string&) override { publisher_->publish(summary.line); }
  void on_alert(const AlertEvent&, const std::string& line) override { publisher_->publish(line); }
  void add_metrics(DaemonMetrics& metrics) const override { metrics.publisher = publisher_->stats(); }
  void stop() override { publisher_->stop(); }

 private:
  std::unique_ptr<Publisher> publisher_;
};

// The station's database ([storage], docs/storage.md): every Nth posture,
// every summary and alert, the station's notes.
class StoreSink final : public PostureSink {
 public:
  StoreSink(std::unique_ptr<Store> store, std::uint64_t posture_every)
      : store_(std::move(store)), posture_every_(posture_every) {}

  std::string_view name() const override { return "storage"; }
  void on_posture(const PostureEvent& event) override;
  void on_summary(const SummaryLine& summary, const std::string& worker) override;
  void on_alert(const AlertEvent& event, const std::string& line) override;
  void on_note(NoteLevel level, std::string_view message) override;
  void add_status(std::string& text) const override;
  void stop() override { store_->stop(); }

 private:
  std::unique_ptr<Store> store_;
  const std::uint64_t posture_every_;
};

// The site's broker ([mqtt], docs/fleet.md).
class MqttSink final : public PostureSink {
 public:
  explicit MqttSink(std::unique_ptr<MqttPublisher> mqtt) : mqtt_(std::move(mqtt)) {}

  std::string_view name() const override { return "mqtt"; }
  void on_posture(const PostureEvent& event) override { mqtt_->offer_posture(event.posture.t_ns, event.line); }
  void on_summary(const SummaryLine& summary, const std::string&) override { mqtt_->publish_summary(summary.line); }
  void on_alert(const AlertEvent&, const std::string& line) override { mqtt_->publish_alert(line); }
  void add_metrics(DaemonMetrics& metrics) const override { metrics.mqtt = mqtt_->stats(); }
  void add_status(std::string& text) const override;
  void stop() override { mqtt_->stop(); }  // sends what it can, says "offline"

 private:
  std::unique_ptr<MqttPublisher> mqtt_;
};

// The buzzer or lamp ([alerts] gpio_chip). A line that could not be opened
// at start is a sink too: it says so on the status line.
class AlertLineSink final : public PostureSink {
 public:
  explicit AlertLineSink(std::unique_ptr<AlertOutput> output) : output_(std::move(output)) {}
  AlertLineSink() = default;  // the line could not be opened
  bool is_open() const { return output_ != nullptr; }

  std::string_view name() const override { return "alert line"; }
  void on_posture(const PostureEvent&) override {}
  // The output keeps track of raised rules even when silent, so that
  // leaving silent mode signals what is still raised.
  void on_alert(const AlertEvent& event, const std::string&) override {
    if (output_) output_->on_event(event);
  }
  void set_silent(bool silent) {
    if (output_) output_->set_silent(silent);
  }
  void add_status(std::string& text) const override;
  void stop() override {
    if (output_) output_->stop();
  }

 private:
  std::unique_ptr<AlertOutput> output_;
};

// The HTTP server ([http], docs/daemon.md "Live view") and the live view
// whose pictures it serves; the server runs on the daemon's network loop.
class LiveViewSink final : public PostureSink {
 public:
  // Starts the live view's render thread; the server comes with start().
  LiveViewSink(const CameraRig& rig, LiveViewOptions view);
  // Binds and starts serving on `io`.
  Status start(boost::asio::io_context& io, const HttpOptions& options, HttpHandlers handlers, StationInfo station);
  std::uint16_t port() const { return http_->port(); }

  std::string_view name() const override { return "live view"; }
  void on_posture(const PostureEvent& event) override {
    if (!event.pair.camera_lost) live_->offer(event.pair, event.posture, event.trace);
  }
  // HttpStats and LiveViewStats: the server adds them to what it serves.
  void stop() override {
    if (http_) http_->stop();
    live_->stop();
  }

 private:
  std::unique_ptr<LiveView> live_;
  std::unique_ptr<HttpServer> http_;  // declared after live_: destroyed first
};

}  // namespace spinewatch
