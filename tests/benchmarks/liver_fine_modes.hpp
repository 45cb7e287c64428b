#pragma once
// liverFine (the real liver mesh of ../shared/data/liver), its gravity scene and its lowest
// vibration modes: the reduced benchmarks' common liver.
#include <optional>
#include <string>
#include <utility>

#include "nav/reduced/reduction.hpp"
#include "nav/tissue/liver_scenes.hpp"

namespace nav::bench {

/// liverFine, its gravity scene and its lowest modes.
struct LiverFineModes {
  TetMesh mesh;
  TissueScene scene;
  ReducedBasis modes;
};

/// Builds liverFine with its `mode_count` lowest modes; nullopt when the data is missing.
inline std::optional<LiverFineModes> load_liver_fine_modes(int mode_count) {
  auto mesh = load_liver_mesh(NAV_SHARED_LIVER_DIR, 22019);
  if (!mesh.ok()) return std::nullopt;
  LiverFineModes l{std::move(mesh).value(), {}, {}};
  l.scene = liver_scenes(l.mesh).front().scene;
  ReductionOptions options;
  options.source = ReducedBasisSource::linear_modes;
  options.basis_size = mode_count;
  auto modes = make_modal_basis(l.mesh, l.scene, TissueSolverOptions{}, options);
  if (!modes.ok()) return std::nullopt;
  l.modes = std::move(modes).value();
  return l;
}

}  // namespace nav::bench
