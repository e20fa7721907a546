#pragma once
// The trigger-controller firmware running in simavr (ATmega328P, 16 MHz):
// records every transition of the camera and sync pins with its cycle
// count, and talks to the UART at the real byte rate.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

struct avr_t;
struct avr_irq_t;
struct elf_firmware_t;

namespace spinewatch::firmware_test {

constexpr std::uint64_t kCpuHz = 16'000'000;
constexpr std::uint64_t kCyclesPerTick = 8;  // Timer1 at clk/8
constexpr std::uint64_t kCyclesPerUs = kCpuHz / 1'000'000;

enum class Pin { CameraA, CameraB, Sync };

struct Edge {
  std::uint64_t cycle;
  bool high;
};

struct Pulse {
  std::uint64_t rise;  // cycles
  std::uint64_t fall;
  std::uint64_t width() const { return fall - rise; }
};

class SimController {
 public:
  // Boots the firmware; `eeprom` (when given) replaces the EEPROM content first.
  explicit SimController(const std::vector<std::uint8_t>* eeprom = nullptr);
  ~SimController();
  SimController(const SimController&) = delete;
  SimController& operator=(const SimController&) = delete;

  void run_us(std::uint64_t us);
  void run_until_cycle(std::uint64_t cycle);
  // Sends `line` + "\n" at 115200 baud and runs until a reply line arrives
  // (nothing after `timeout_us` of simulated time).
  std::optional<std::string> command(const std::string& line, std::uint64_t timeout_us = 20'000);
  void send_raw(const std::string& bytes);  // queued, sent at the byte rate while running
  std::vector<std::string> take_lines();    // reply lines received so far

  // Power-cycle style reset: the core and peripherals restart, the EEPROM stays.
  void reset();

  std::uint64_t cycle() const;
  const std::vector<Edge>& edges(Pin pin) const { return edges_[static_cast<int>(pin)]; }
  std::vector<Pulse> pulses(Pin pin, std::uint64_t from_cycle = 0) const;
  std::vector<std::uint8_t> eeprom(std::size_t size) const;

 private:
  static void on_pin(avr_irq_t* irq, std::uint32_t value, void* param);
  static void on_uart_byte(avr_irq_t* irq, std::uint32_t value, void* param);
  void step();

  elf_firmware_t* firmware_ = nullptr;  // simavr keeps pointers into its symbols: freed after avr_
  avr_t* avr_ = nullptr;
  std::vector<Edge> edges_[3];
  struct PinHook {
    SimController* self;
    int index;
  } hooks_[3]{};
  std::string tx_queue_;
  std::uint64_t next_tx_cycle_ = 0;
  std::string rx_partial_;
  std::vector<std::string> rx_lines_;
};

}  // namespace spinewatch::firmware_test
