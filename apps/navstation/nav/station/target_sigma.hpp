#pragma once
// A predicted target's uncertainty as displays draw it: one radius, the largest 1-sigma extent
// of its position covariance (the OpenIGTLink bridge's tumour points, session exports).
#include "nav/dds/samples.hpp"

namespace nav::station {

/// The largest 1-sigma radius of a position covariance (m): the square root of its largest
/// eigenvalue.
double sigma_radius_m(const dds::Covariance3& covariance_m2);

}  // namespace nav::station
