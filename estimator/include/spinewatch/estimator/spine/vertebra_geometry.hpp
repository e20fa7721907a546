#pragma once
// Figures for the parametric vertebra solids and the discs
// (config/vertebra-geometry.toml, embedded at build time).
#include <string_view>

#include "spinewatch/estimator/spine/mass_properties.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct BodyDims {
  double height_mm = 0, width_mm = 0, depth_mm = 0;  // Y, Z, X extents of the vertebral body
};

// Fractions of the body dimensions (see the config file for each).
struct PosteriorElements {
  double pedicle_width = 0, pedicle_height = 0, pedicle_length = 0, pedicle_spacing = 0;
  double lamina_thickness = 0, lamina_height = 0;
  double spinous_length = 0, spinous_height = 0, spinous_width = 0, spinous_droop_deg = 0;
  double transverse_reach = 0, transverse_thickness = 0;
};

struct DiscFigures {
  double attach_fraction = 0.5;
  double max_spring_bending_share = 0.5;
  double damping_n_s_per_m = 1200;
  double tension_ratio = 0.1;
  double shear_fraction = 0.1;
};

struct VertebraGeometry {
  double bone_density_kg_per_m3 = 1250;
  PosteriorElements thoracic, lumbar;
  DiscFigures disc;
};

Result<VertebraGeometry> parse_vertebra_geometry(std::string_view toml_text, std::string_view source);
const VertebraGeometry& generic_vertebra_geometry();
std::string_view vertebra_geometry_toml();

// The vertebral body alone: an elliptic cylinder centred on the origin.
Solid vertebral_body_solid(const BodyDims& dims);
// Body plus pedicles, laminae, spinous and transverse processes.
Solid vertebra_solid(const BodyDims& dims, const PosteriorElements& posterior);

}  // namespace spinewatch
