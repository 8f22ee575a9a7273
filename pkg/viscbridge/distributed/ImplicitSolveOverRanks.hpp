// The implicit viscous system (physics.md §4, P15) of a scene split by yade.mpy, solved as one
// system over all ranks: the backward-Euler solve must couple the bridges that cross subdomain
// boundaries, or each subdomain would integrate its boundary particles against frozen neighbours.
//
// Each rank holds the rows of the bodies it owns; the bodies of other workers that its bridges
// touch ("ghosts", mpy's mirrors) enter its system as prescribed (the rank's own block stays
// exactly its rows), and their values in every CG vector come from their owners by a halo
// exchange along mpy's own intersection lists.  Dot products are sums over the ranks, so every
// rank runs the same iterations and stops at the same one, at the serial solver's tolerance on
// the global relative residual ‖r‖/‖b‖.  The preconditioner is block Jacobi over the
// subdomains: each rank's lagged Cholesky factorisation of its own rows (or its 6×6 blocks), i.e.
// additive Schwarz without overlap.
#pragma once
#include "viscbridge/core/linalg/ImplicitViscousSystem.hpp"
#include <core/Scene.hpp>
#include <vector>

namespace yade {

// Collective.  `sys` is this rank's system (owned bodies free, ghosts and everything else
// prescribed), `ids` the body id of each of its bodies, `x` the starting guess of the owned
// entries; x receives the solution, ghosts included.  No direct fallback: if CG does not reach
// `tolerance` within maxIterations the report says so on every rank (converged = false).
viscbridge::SolveReport solveOverRanks(const Scene* scene, const viscbridge::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids,
                                       Eigen::VectorXd& x, double tolerance, int maxIterations, const viscbridge::Preconditioner* pre);

} // namespace yade
