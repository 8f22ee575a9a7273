// ViscBridgeImplicitSolver: the step's bridge and body arrays gathered from the interactions (P15a),
// and the warm start of the solve.
#include "viscbridge/engines/ViscBridgeImplicitSolverGathered.hpp"
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/engines/ViscBridgeImplicitWarmStart.hpp"
#include "viscbridge/yade/OrderedWetContacts.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include <core/Clump.hpp>
#include <core/Scene.hpp>
#include <pkg/dem/NewtonIntegrator.hpp>
#include <pkg/dem/ScGeom.hpp>

namespace yade {

using namespace implicit_solver;

// The bridges the law described this step, and the bodies they touch with every other force of the
// step (gravity included, as Newton will add it).  A clump stands for its members: its six
// velocities are the unknowns, and a member's bridge acts on it at the member's centre (P15a).
// The scans run on all threads; every list comes out in the same order as from one thread.
ViscBridgeImplicitSolver::Gathered ViscBridgeImplicitSolver::gather(const NewtonIntegrator& newton)
{
	scene->forces.sync();
	Gathered g;
	describedBridges(g);
	touched.assign(scene->bodies->size(), -1);
	for (const auto& [id1, id2] : g.ends)
		touched[moving(id1)] = touched[moving(id2)] = 0;
	for (Body::id_t id = 0; id < static_cast<Body::id_t>(touched.size()); ++id)
		if (touched[id] >= 0) {
			touched[id] = static_cast<int>(g.ids.size());
			g.ids.push_back(id);
		}
	const long nBodies = static_cast<long>(g.ids.size()), nBridges = static_cast<long>(g.described.size());
	g.bodies.resize(nBodies);
	g.system.resize(nBridges);
	g.pattern.resize(nBodies + nBridges);
	const auto own      = distributed::ownership(scene); // [MPI] a rank solves for its own bodies
	const bool branches = preconditioner == multigrid || preconditioner == automatic; // only the multigrid reads them (its rigid motions)
#pragma omp parallel
	{
#pragma omp for schedule(static)
		for (long i = 0; i < nBodies; ++i) {
			g.bodies[i]   = systemBody(*Body::byId(g.ids[i], scene), own, newton);
			long freeBits = 0;
			for (int d = 0; d < 6; ++d)
				freeBits |= g.bodies[i].free[d] ? (1L << d) : 0;
			g.pattern[i] = g.ids[i] * 64 + freeBits;
		}
#pragma omp for schedule(static)
		for (long k = 0; k < nBridges; ++k) {
			vb::SystemBridge& c = g.system[k];
			c.body1             = touched[moving(g.ends[k][0])];
			c.body2             = touched[moving(g.ends[k][1])];
			c.block             = g.owners[k]->implicitBlock;
			c.block.r1 += armInClump(g.ends[k][0]);
			c.block.r2 += armInClump(g.ends[k][1]);
			c.shiftVel          = scene->isPeriodic ? Vector3r(scene->cell->intrShiftVel(g.described[k]->cellDist)) : Vector3r::Zero();
			if (branches)
				c.branch = Body::byId(g.ids[c.body2], scene)->state->pos - Body::byId(g.ids[c.body1], scene)->state->pos
				        + (scene->isPeriodic ? Vector3r(scene->cell->intrShiftPos(g.described[k]->cellDist)) : Vector3r::Zero());
			g.pattern[nBodies + k] = -(static_cast<long>(std::min(c.body1, c.body2)) * (1L << 31) + std::max(c.body1, c.body2)) - 1;
		}
	}
	return g;
}

// The body whose velocities move body `id`: its clump for a clump member, else itself.
Body::id_t ViscBridgeImplicitSolver::moving(Body::id_t id) const
{
	const Body& b = *Body::byId(id, scene);
	return b.isClumpMember() ? b.clumpId : id;
}

// From the centre of the body that moves body `id` to body id's centre (0 unless a clump member).
Vector3r ViscBridgeImplicitSolver::armInClump(Body::id_t id) const
{
	const Body& b = *Body::byId(id, scene);
	return b.isClumpMember() ? Vector3r(b.state->pos - Body::byId(b.clumpId, scene)->state->pos) : Vector3r::Zero();
}

// The bridges the law described this step, in the order of their bodies' ids (OrderedWetContacts:
// the same on any number of threads), tested on all threads.
void ViscBridgeImplicitSolver::describedBridges(Gathered& g) const
{
	const long iter = scene->iter;
	orderedWetContacts(
	        scene, [iter](const Interaction&, const ViscBridgePhys& ph) { return ph.bridge && ph.implicitBlock.valid && ph.implicitBlockIter == iter; },
	        described);
	for (const auto& [key, I] : described) {
		g.described.push_back(I);
		g.owners.push_back(static_cast<ViscBridgePhys*>(I->phys.get()));
		g.ends.push_back({ I->getId1(), I->getId2() });
	}
}

vb::SystemBody ViscBridgeImplicitSolver::systemBody(const Body& b, const distributed::Ownership& own, const NewtonIntegrator& newton) const
{
	const State&   st = *b.state;
	vb::SystemBody sb;
	sb.mass    = st.mass;
	sb.inertia = rotationalInertia(b, newton);
	sb.vel     = st.vel;
	sb.angVel  = st.angVel;
	const bool moves = b.isDynamic() && st.mass > 0 && own.body(b); // [MPI] other ranks' bodies: ghosts (prescribed here)
	for (int d = 0; d < 6; ++d)
		sb.free[d] = moves && !(st.blockedDOFs & State::axisDOF(d % 3, d >= 3));
	if (moves) {
		sb.force  = scene->forces.getForce(b.id);
		sb.torque = scene->forces.getTorque(b.id);
		if (b.isClump()) b.shape->cast<Clump>().addForceTorqueFromMembers(&st, scene, sb.force, sb.torque); // as Newton sums them
		for (int d = 0; d < 3; ++d)
			if (sb.free[d]) sb.force[d] += st.mass * newton.gravity[d]; // Newton adds gravity to unblocked components
	}
	return sb;
}

// The inertia tensor Newton's rotation update applies, in the global frame: the principal one turned
// by the orientation where Newton integrates an aspherical body (a clump) exactly; otherwise Newton
// divides the torque by the principal moments component by component (a sphere: I·1).
Matrix3r ViscBridgeImplicitSolver::rotationalInertia(const Body& b, const NewtonIntegrator& newton)
{
	const State& st         = *b.state;
	const bool   aspherical = newton.exactAsphericalRot && b.isAspherical() && (st.blockedDOFs & State::DOF_RXRYRZ) == State::DOF_NONE;
	if (!aspherical) return st.inertia.asDiagonal();
	const Matrix3r turn = st.ori.toRotationMatrix();
	return turn * st.inertia.asDiagonal() * turn.transpose();
}

// The velocities last step's viscous forces would give now (else the current ones).
Eigen::VectorXd ViscBridgeImplicitSolver::warmStartGuess(const vb::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids) const
{
	Eigen::VectorXd x = sys.currentVelocities();
	if (!warmStart || last->force.size() != scene->bodies->size()) return x;
	for (size_t i = 0; i < ids.size(); ++i) {
		const vb::SystemBody& b = sys.bodies()[i];
		if (b.mass > 0) x.segment<3>(6 * i) += scene->dt * (b.force + last->force[ids[i]]) / b.mass;
		if (b.inertia.trace() > 0) x.segment<3>(6 * i + 3) += scene->dt * b.inertia.ldlt().solve(b.torque + last->torque[ids[i]]);
	}
	return x;
}

} // namespace yade
