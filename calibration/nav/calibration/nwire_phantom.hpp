#pragma once
// The N-wire (Z-wire) phantom of a probe spatial calibration, as PLUS describes it in its
// device-set XML: each pattern is three wires, the outer two parallel and the middle one
// diagonal; the image plane cuts them in three collinear dots, and the ratio of the dots'
// distances places the middle wire's dot in phantom coordinates (Comeau et al. 2000).
#include <array>
#include <string>
#include <vector>

#include "nav/calibration/rigid_transform.hpp"
#include "nav/core/error.hpp"

namespace nav::calibration {

/// One wire, front and back end points in the phantom frame (metres).
struct PhantomWire {
  Eigen::Vector3d front_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d back_m = Eigen::Vector3d::Zero();
};

/// Three wires in image order: parallel, diagonal, parallel.
using NWirePattern = std::array<PhantomWire, 3>;

/// The phantom: its N patterns (in the XML's order) and its registration to the reference
/// marker, reference_from_phantom (the XML's Phantom-to-Reference transform).
struct NWirePhantom {
  std::vector<NWirePattern> patterns;
  Transform reference_from_phantom = Transform::Identity();
};

/// Reads <PhantomDefinition> (Pattern Type="NWire", Wire EndPointFront/EndPointBack in mm)
/// and <Transform From="Phantom" To="Reference" Matrix=...> from a PLUS device-set XML.
/// Errors name the file, line and element.
Result<NWirePhantom> load_nwire_phantom(const std::string& path);
/// The same from XML text; `path` only names it in errors.
Result<NWirePhantom> parse_nwire_phantom(const std::string& xml, const std::string& path);

/// The middle wire's point in phantom coordinates, from the three image dots of a pattern
/// (any consistent unit): the middle dot divides the outer two in the ratio it divides the
/// wires' cross-section.
Eigen::Vector3d middle_wire_point(const NWirePattern& pattern, const Eigen::Vector2d& first_px,
                                  const Eigen::Vector2d& middle_px, const Eigen::Vector2d& last_px);

}  // namespace nav::calibration
