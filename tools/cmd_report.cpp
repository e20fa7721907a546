// spinewatch report: an exposure report over a time range of what a station
// stored (docs/interfaces.md §4; docs/exposure.md): DIR/report.html (inline SVG,
// nothing external) and DIR/summaries.csv.
#include <filesystem>
#include <memory>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "output_file.hpp"
#include "spinewatch/daemon/stored_lines.hpp"
#include "spinewatch/report/html_report.hpp"

namespace spinewatch::cli {

void add_report_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    std::string db, summaries, from, to, worker, out, period_a, period_b;
  };
  auto opts = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("report", "Exposure report (HTML with figures, and CSV) over a time range");
  auto* db = cmd->add_option("--db", opts->db, "the station's database ([storage] path)");
  auto* file = cmd->add_option("--summaries", opts->summaries,
                               "summary lines (replay --summaries, or a recorded stream)");
  db->excludes(file);
  cmd->add_option("--from", opts->from, "first interval start: UTC (2026-12-02T08:00:00Z) or seconds of the stream");
  cmd->add_option("--to", opts->to, "intervals starting before this");
  cmd->add_option("--worker", opts->worker, "only this worker's intervals (set_worker id)");
  cmd->add_option("--period-a", opts->period_a, "comparison period A, FROM/TO (default: first half)");
  cmd->add_option("--period-b", opts->period_b, "comparison period B, FROM/TO (default: second half)");
  cmd->add_option("--out", opts->out, "directory for report.html and summaries.csv")->required();
  cmd->callback([opts, &exit_code] {
    using namespace report;
    if (opts->db.empty() == opts->summaries.empty())
      return exit_code.fail(Error{"give one of --db FILE or --summaries FILE"}, 2);
    if (opts->period_a.empty() != opts->period_b.empty())
      return exit_code.fail(Error{"--period-a and --period-b go together"}, 2);
    Selection selection;
    std::string words;
    for (auto [text, bound, name] : {std::tuple{&opts->from, &selection.from, "--from"}, std::tuple{&opts->to, &selection.to, "--to"}}) {
      if (text->empty()) continue;
      auto t = parse_time_point(*text);
      if (!t) return exit_code.fail(Error{std::string(name) + " " + t.error().message}, 2);
      *bound = *t;
      words += std::string(words.empty() ? "" : ", ") + (name + 2) + " " + *text;
    }
    if (!opts->worker.empty()) {
      selection.worker = opts->worker;
      words += (words.empty() ? "" : ", ") + std::string("worker ") + opts->worker;
    }
    ReportInput input;
    for (auto [text, out, name] : {std::tuple{&opts->period_a, &input.period_a, "--period-a"},
                                   std::tuple{&opts->period_b, &input.period_b, "--period-b"}}) {
      if (text->empty()) continue;
      auto p = parse_period(*text);
      if (!p) return exit_code.fail(Error{std::string(name) + " " + p.error().message}, 2);
      *out = *p;
    }
    Result<std::vector<LabelledSummary>> all = std::vector<LabelledSummary>{};
    if (!opts->db.empty()) {
      input.source = "database " + opts->db;
      auto lines = read_stored_summary_lines(opts->db);
      if (!lines) return exit_code.fail(lines.error());
      for (std::size_t i = 0; i < lines->size(); ++i) {
        auto s = decode_summary((*lines)[i], fmt::format("{}: summary {}", opts->db, i + 1));
        if (!s) return exit_code.fail(s.error());
        all->push_back(std::move(s).value());
      }
    } else {
      input.source = "summaries " + opts->summaries;
      all = read_summary_file(opts->summaries);
      if (!all) return exit_code.fail(all.error());
    }
    auto selected = select(std::move(all).value(), selection);
    if (!selected) return exit_code.fail(selected.error());
    input.intervals = std::move(selected).value();
    input.selection = words.empty() ? "everything" : words;
    auto html = render_html(input);
    if (!html) return exit_code.fail(html.error());
    std::error_code ec;
    std::filesystem::create_directories(opts->out, ec);
    if (ec) return exit_code.fail(Error{opts->out + ": cannot be created: " + ec.message()});
    const std::filesystem::path dir(opts->out);
    if (auto s = write_output((dir / "report.html").string(), *html); !s) return exit_code.fail(s.error());
    if (auto s = write_output((dir / "summaries.csv").string(), render_csv(input.intervals)); !s)
      return exit_code.fail(s.error());
    spdlog::info("report: {} interval{} → {}/report.html, {}/summaries.csv", input.intervals.size(),
                 input.intervals.size() == 1 ? "" : "s", opts->out, opts->out);
  });
}

}  // namespace spinewatch::cli
