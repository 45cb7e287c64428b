#pragma once
// The exact reduced St Venant-Kirchhoff force as a cubic polynomial in q (Barbic and James
// 2005): f(q) = -(K1 q + Q m2(q) + T m3(q)), with m2 the monomials q_a q_b (a <= b) and m3
// the monomials q_a q_b q_c (a <= b <= c), in lexicographic order. Coefficients (row-major,
// one row per reduced force component): K1 (r x r), then Q (r x r(r+1)/2), then
// T (r x r(r+1)(r+2)/6), concatenated in ReducedBasis::polynomial_coefficients. Internal to
// rtlib/nav/reduced; no incompressibility penalty (it is not a polynomial) and no lift.
#include <cstddef>
#include <span>
#include <vector>

#include "nav/reduced/reduced_tables.hpp"
#include "nav/tissue/tet_fem_tables.hpp"

namespace nav::detail {

/// Number of coefficients of the polynomial for basis size r.
std::size_t stvk_polynomial_size(int r);

/// The coefficients of the basis columns `rows` ((3 node_count) x r, row-major) on the
/// elements of `tables` (init time).
std::vector<double> build_stvk_polynomial(const TetFemTables& tables, std::span<const double> rows, int r);

/// force = f(q); when tangent is not empty it gets -df/dq (r x r, symmetrised). No allocation:
/// `monomials` holds at least r(r+1)/2 + r(r+1)(r+2)/6 values.
void evaluate_stvk_polynomial(const ReducedTables& t, std::span<const double> q, std::span<double> monomials,
                              std::span<double> force, std::span<double> tangent) noexcept;

}  // namespace nav::detail
