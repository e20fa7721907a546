#pragma once
// Inline SVG for the report's figures: a canvas with a plot area and
// linear scales, writing elements as text (no external resources).
#include <string>
#include <string_view>

namespace spinewatch::report {

// Text for HTML/SVG content and attribute values.
std::string escape_xml(std::string_view text);

struct Scale {  // data → pixels, linear
  double d0 = 0, d1 = 1, p0 = 0, p1 = 1;
  double operator()(double v) const { return d1 == d0 ? p0 : p0 + (v - d0) * (p1 - p0) / (d1 - d0); }
};

class SvgCanvas {
 public:
  // The plot area is the canvas less the margins.
  SvgCanvas(std::string id, int width, int height, int left, int right, int top, int bottom, std::string title);

  double plot_left() const { return left_; }
  double plot_right() const { return width_ - right_; }
  double plot_top() const { return top_; }
  double plot_bottom() const { return height_ - bottom_; }
  Scale x_scale(double d0, double d1) const { return {d0, d1, plot_left(), plot_right()}; }
  Scale y_scale(double d0, double d1) const { return {d0, d1, plot_bottom(), plot_top()}; }

  // `extra`: further attributes, written as given (class, data-*).
  void rect(double x, double y, double w, double h, std::string_view fill, std::string_view extra = {});
  void line(double x1, double y1, double x2, double y2, std::string_view stroke, double width = 1,
            std::string_view extra = {});
  void circle(double x, double y, double r, std::string_view fill, std::string_view extra = {});
  void polyline(std::string_view points, std::string_view stroke, double width, std::string_view extra = {});
  void text(double x, double y, std::string_view content, std::string_view anchor = "start", int size = 11,
            std::string_view extra = {});
  // Horizontal grid line with its label at the left of the plot area.
  void y_tick(double y, std::string_view label);
  void x_tick(double x, std::string_view label);
  void raw(std::string_view element) { body_ += element; }

  std::string str() const;

 private:
  std::string id_, title_, body_;
  int width_, height_, left_, right_, top_, bottom_;
};

}  // namespace spinewatch::report
