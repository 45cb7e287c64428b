#include "nav/connective/organ_ligaments.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace nav {

Result<OrganLigaments> make_organ_ligaments(const TetMesh& organ, const std::vector<LigamentSpec>& specs,
                                            const ElasticMaterial& material, const FrameTissueOptions& options,
                                            const Point3& gravity_m_s2, bool stabilise) {
  std::vector<FrameLayout> layouts;
  std::vector<FrameGrid> grids;
  FrameSupports supports;
  std::int32_t first_frame = 0;
  for (std::size_t l = 0; l < specs.size(); ++l) {
    const LigamentSpec& spec = specs[l];
    const std::string field = "ligament " + std::to_string(l);
    // The organ's upper surface under each column of frames: the highest node within half a
    // spacing of it; the lowest layer goes embed_m under the lowest of them.
    const double dx = spec.width_m / (spec.frames[0] - 1), dy = spec.depth_m / (spec.frames[1] - 1);
    double top_m = 1e300;
    for (int j = 0; j < spec.frames[1]; ++j)
      for (int i = 0; i < spec.frames[0]; ++i) {
        const double x = spec.footprint_centre_m[0] - 0.5 * spec.width_m + i * dx,
                     y = spec.footprint_centre_m[1] - 0.5 * spec.depth_m + j * dy;
        double column_m = -1e300;
        for (const Point3& p : organ.nodes_m)
          if (std::abs(p[0] - x) <= 0.5 * dx && std::abs(p[1] - y) <= 0.5 * dy) column_m = std::max(column_m, p[2]);
        if (column_m < -1e299)
          return Error{
              .message = "no organ node under the footprint's column " + std::to_string(i) + ", " + std::to_string(j),
              .field = field};
        top_m = std::min(top_m, column_m);
      }
    FrameGrid grid;
    grid.origin_m = {spec.footprint_centre_m[0] - 0.5 * spec.width_m, spec.footprint_centre_m[1] - 0.5 * spec.depth_m,
                     top_m - spec.embed_m};
    grid.counts = spec.frames;
    grid.spacing_m = {spec.width_m / (spec.frames[0] - 1), spec.depth_m / (spec.frames[1] - 1),
                      spec.length_m / (spec.frames[2] - 1)};
    auto layout = make_grid_layout(grid);
    if (!layout.ok()) return Error{.message = layout.error().message, .field = field + "." + layout.error().field};
    const FrameLayout& made = layout.value();
    for (std::size_t f = 0; f < made.frames_m.size(); ++f) {
      const auto index = first_frame + static_cast<std::int32_t>(f);
      if (made.frames_m[f][2] <= grid.origin_m[2] + 1e-12) supports.driven_frames.push_back(index);
      if (made.frames_m[f][2] >= grid.origin_m[2] + spec.length_m - 1e-12) supports.fixed_frames.push_back(index);
    }
    first_frame += static_cast<std::int32_t>(made.frames_m.size());
    layouts.push_back(made);
    grids.push_back(grid);
  }
  FrameTissueScene scene;
  scene.layout = join_layouts(layouts);
  scene.material = material;
  scene.gravity_m_s2 = gravity_m_s2;
  scene.supports = supports;
  auto model = make_frame_tissue_model(scene, options);
  if (!model.ok()) return model.error();
  auto attachment = attach_driven_frames(model.value(), organ, stabilise);
  if (!attachment.ok()) return attachment.error();
  return OrganLigaments{std::move(model.value()), std::move(attachment.value()), std::move(grids)};
}

}  // namespace nav
