// What the parts of ViscBridgeImplicitSolver share: the step's bridge arrays (gather) and the
// preconditioners' names.  Included only by ViscBridgeImplicitSolver*.cpp.
#pragma once
#include "viscbridge/engines/ViscBridgeImplicitSolver.hpp"
#include <array>
#include <string>
#include <vector>

namespace yade {
class Interaction;

namespace implicit_solver {
	namespace vb = viscbridge;
	// the preconditioners, by name: two lagged ones, block Jacobi (not lagged), and the choice
	// between the two lagged ones by the factor's size (the default)
	constexpr std::array<const char*, 4> preconditionerNames { "cholesky", "multigrid", "jacobi", "auto" };
	inline const std::string             cholesky = preconditionerNames[0], multigrid = preconditionerNames[1], jacobi = preconditionerNames[2],
	                         automatic = preconditionerNames[3];
}

// The bridges the law described this step and the bodies they touch, in the system's order.
struct ViscBridgeImplicitSolver::Gathered {
	std::vector<Interaction*>    described; // the bridges, in the system's order
	std::vector<ViscBridgePhys*> owners;
	std::vector<std::array<Body::id_t, 2>> ends; // their bodies' ids
	std::vector<Body::id_t>      ids; // the system's bodies, ordered by id (same bodies, same system)
	std::vector<viscbridge::SystemBody>  bodies;
	std::vector<viscbridge::SystemBridge> system;
	std::vector<long>            pattern; // bodies with their free components, and bridges (in the interactions' order): decides whether the factor's analysis still holds
};

} // namespace yade
