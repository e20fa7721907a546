#include "spinewatch/report/svg.hpp"

#include <fmt/format.h>

namespace spinewatch::report {

std::string escape_xml(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

SvgCanvas::SvgCanvas(std::string id, int width, int height, int left, int right, int top, int bottom, std::string title)
    : id_(std::move(id)), title_(std::move(title)), width_(width), height_(height), left_(left), right_(right),
      top_(top), bottom_(bottom) {}

void SvgCanvas::rect(double x, double y, double w, double h, std::string_view fill, std::string_view extra) {
  body_ += fmt::format("<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"{}\" {}/>\n", x, y,
                       w, h, fill, extra);
}

void SvgCanvas::line(double x1, double y1, double x2, double y2, std::string_view stroke, double width,
                     std::string_view extra) {
  body_ += fmt::format("<line x1=\"{:.2f}\" y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\" stroke=\"{}\" stroke-width=\"{}\" {}/>\n",
                       x1, y1, x2, y2, stroke, width, extra);
}

void SvgCanvas::circle(double x, double y, double r, std::string_view fill, std::string_view extra) {
  body_ += fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"{}\" fill=\"{}\" {}/>\n", x, y, r, fill, extra);
}

void SvgCanvas::polyline(std::string_view points, std::string_view stroke, double width, std::string_view extra) {
  body_ += fmt::format("<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"{}\" {}/>\n", points,
                       stroke, width, extra);
}

void SvgCanvas::text(double x, double y, std::string_view content, std::string_view anchor, int size,
                     std::string_view extra) {
  body_ += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"{}\" font-size=\"{}\" {}>{}</text>\n", x, y,
                       anchor, size, extra, escape_xml(content));
}

void SvgCanvas::y_tick(double y, std::string_view label) {
  line(plot_left(), y, plot_right(), y, "#ddd");
  text(plot_left() - 6, y + 4, label, "end", 10);
}

void SvgCanvas::x_tick(double x, std::string_view label) {
  line(x, plot_bottom(), x, plot_bottom() + 4, "#888");
  text(x, plot_bottom() + 16, label, "middle", 10);
}

std::string SvgCanvas::str() const {
  return fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"{}\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\" "
      "role=\"img\" aria-label=\"{}\" font-family=\"sans-serif\">\n"
      "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#888\"/>\n{}</svg>\n",
      id_, width_, height_, width_, height_, escape_xml(title_), left_, top_, width_ - left_ - right_,
      height_ - top_ - bottom_, body_);
}

}  // namespace spinewatch::report
