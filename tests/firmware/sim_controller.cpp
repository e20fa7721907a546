#include "sim_controller.hpp"

#include <avr_eeprom.h>
#include <avr_ioport.h>
#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_elf.h>

#include <cstdarg>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

// simavr 1.6's avr_terminate() leaves the core, its IRQ pool and IRQ
// names allocated (each simulator instance leaks them once); that is the
// library's teardown, not ours, so LeakSanitizer is told to ignore
// allocations made inside libsimavr. Our own allocations stay checked.
extern "C" const char* __lsan_default_suppressions() { return "leak:libsimavr\n"; }

namespace spinewatch::firmware_test {

namespace {

// 10 bits per byte at 115200 baud, rounded up.
constexpr std::uint64_t kCyclesPerByte = (kCpuHz * 10 + 115200 - 1) / 115200;

// simavr prints its own chatter (timer set-up, firmware sections) on stdout.
void quiet_logger(avr_t*, const int level, const char* format, va_list args) {
  if (level <= LOG_ERROR) std::vfprintf(stderr, format, args);
}

// elf_read_firmware mallocs the sections and the symbol table; simavr
// never frees them.
void free_firmware(elf_firmware_t* f) {
  if (!f) return;
  std::free(f->flash);
  std::free(f->eeprom);
  std::free(f->fuse);
  std::free(f->lockbits);
  for (std::uint32_t i = 0; i < f->symbolcount; ++i) std::free(f->symbol[i]);
  std::free(f->symbol);
  delete f;
}

// simavr sleeps in real time while the MCU sleeps (to run "at speed");
// the tests want simulated time as fast as the host can go.
void no_wall_clock_sleep(avr_t*, avr_cycle_count_t) {}

}  // namespace

SimController::SimController(const std::vector<std::uint8_t>* eeprom) {
  avr_global_logger_set(quiet_logger);
  firmware_ = new elf_firmware_t{};
  if (elf_read_firmware(SPINEWATCH_TRIGGER_ELF, firmware_) != 0) {
    free_firmware(firmware_);
    throw std::runtime_error(std::string("cannot read ") + SPINEWATCH_TRIGGER_ELF);
  }
  firmware_->frequency = kCpuHz;
  avr_ = avr_make_mcu_by_name("atmega328p");
  if (!avr_) {
    free_firmware(firmware_);
    throw std::runtime_error("simavr has no atmega328p");
  }
  avr_init(avr_);
  avr_load_firmware(avr_, firmware_);
  avr_->frequency = kCpuHz;
  avr_->log = LOG_ERROR;
  avr_->sleep = no_wall_clock_sleep;
  if (eeprom) {
    std::vector<std::uint8_t> copy = *eeprom;
    avr_eeprom_desc_t desc{copy.data(), 0, static_cast<std::uint32_t>(copy.size())};
    avr_ioctl(avr_, AVR_IOCTL_EEPROM_SET, &desc);
  }

  const struct {
    char port;
    int bit;
  } pins[3] = {{'B', 1}, {'B', 2}, {'D', 7}};
  for (int i = 0; i < 3; ++i) {
    hooks_[i] = {this, i};
    avr_irq_register_notify(avr_io_getirq(avr_, AVR_IOCTL_IOPORT_GETIRQ(pins[i].port), pins[i].bit), on_pin,
                            &hooks_[i]);
  }
  std::uint32_t flags = 0;
  avr_ioctl(avr_, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
  flags &= ~static_cast<std::uint32_t>(AVR_UART_FLAG_STDIO);
  avr_ioctl(avr_, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
  avr_irq_register_notify(avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT), on_uart_byte, this);
}

SimController::~SimController() {
  avr_terminate(avr_);
  free_firmware(firmware_);
}

void SimController::on_pin(avr_irq_t*, std::uint32_t value, void* param) {
  auto* hook = static_cast<PinHook*>(param);
  auto& edges = hook->self->edges_[hook->index];
  const bool high = (value & 1) != 0;
  // simavr re-raises unchanged levels; only transitions are edges.
  const bool was_high = !edges.empty() && edges.back().high;
  if (high != was_high) edges.push_back({hook->self->avr_->cycle, high});
}

void SimController::on_uart_byte(avr_irq_t*, std::uint32_t value, void* param) {
  auto* self = static_cast<SimController*>(param);
  const char c = static_cast<char>(value & 0xFF);
  if (c == '\n') {
    self->rx_lines_.push_back(self->rx_partial_);
    self->rx_partial_.clear();
  } else {
    self->rx_partial_ += c;
  }
}

void SimController::step() {
  if (!tx_queue_.empty() && avr_->cycle >= next_tx_cycle_) {
    avr_raise_irq(avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT),
                  static_cast<std::uint8_t>(tx_queue_.front()));
    tx_queue_.erase(0, 1);
    next_tx_cycle_ = avr_->cycle + kCyclesPerByte;
  }
  const int state = avr_run(avr_);
  if (state == cpu_Done || state == cpu_Crashed) throw std::runtime_error("the simulated MCU stopped (state " + std::to_string(state) + ")");
}

void SimController::run_until_cycle(std::uint64_t cycle) {
  while (avr_->cycle < cycle) step();
}

void SimController::run_us(std::uint64_t us) { run_until_cycle(avr_->cycle + us * kCyclesPerUs); }

void SimController::send_raw(const std::string& bytes) {
  if (tx_queue_.empty()) next_tx_cycle_ = std::max(next_tx_cycle_, avr_->cycle);
  tx_queue_ += bytes;
}

std::optional<std::string> SimController::command(const std::string& line, std::uint64_t timeout_us) {
  const std::size_t before = rx_lines_.size();
  send_raw(line + "\n");
  const std::uint64_t deadline = avr_->cycle + (line.size() + 1) * kCyclesPerByte + timeout_us * kCyclesPerUs;
  while (rx_lines_.size() == before && avr_->cycle < deadline) step();
  if (rx_lines_.size() == before) return std::nullopt;
  std::string reply = rx_lines_[before];
  rx_lines_.erase(rx_lines_.begin() + static_cast<std::ptrdiff_t>(before));
  return reply;
}

std::vector<std::string> SimController::take_lines() {
  std::vector<std::string> lines;
  lines.swap(rx_lines_);
  return lines;
}

void SimController::reset() {
  avr_reset(avr_);
  tx_queue_.clear();
  rx_partial_.clear();
}

std::uint64_t SimController::cycle() const { return avr_->cycle; }

std::vector<Pulse> SimController::pulses(Pin pin, std::uint64_t from_cycle) const {
  std::vector<Pulse> out;
  const auto& e = edges(pin);
  for (std::size_t i = 0; i + 1 < e.size(); ++i)
    if (e[i].high && !e[i + 1].high && e[i].cycle >= from_cycle) out.push_back({e[i].cycle, e[i + 1].cycle});
  return out;
}

std::vector<std::uint8_t> SimController::eeprom(std::size_t size) const {
  std::vector<std::uint8_t> data(size);
  avr_eeprom_desc_t desc{nullptr, 0, static_cast<std::uint32_t>(size)};
  avr_ioctl(avr_, AVR_IOCTL_EEPROM_GET, &desc);
  if (desc.ee) std::memcpy(data.data(), desc.ee, size);
  return data;
}

}  // namespace spinewatch::firmware_test
