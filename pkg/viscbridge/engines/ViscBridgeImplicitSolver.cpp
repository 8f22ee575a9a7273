// ViscBridgeImplicitSolver (P15): the step, its checks, the solve, the forces and their energy.  The
// step's bridge arrays are gathered in ViscBridgeImplicitSolverGather.cpp, the preconditioner's life
// cycle is in ViscBridgeImplicitSolverPreconditioner.cpp, the error estimate's solves in
// ViscBridgeImplicitSolverEstimate.cpp.
#include "viscbridge/engines/ViscBridgeImplicitSolverGathered.hpp"
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/distributed/ImplicitSolveOverRanks.hpp"
#include "viscbridge/engines/ViscBridgeImplicitWarmStart.hpp"
#include "viscbridge/yade/SceneAttachment.hpp"
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include "viscbridge/core/linalg/ImplicitViscousSystem.hpp"
#include "viscbridge/core/linalg/LaggedPreconditioner.hpp"
#include "viscbridge/core/util/Validation.hpp"
#include "viscbridge/scene/SceneValidation.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include <core/Scene.hpp>
#include <pkg/dem/NewtonIntegrator.hpp>
#include <array>
#include <chrono>
#include <limits>

namespace yade {

using namespace implicit_solver;

CREATE_LOGGER(ViscBridgeImplicitSolver);

void ViscBridgeImplicitSolver::preSave(ViscBridgeImplicitSolver&)
{
	factorisedIter        = -1;
	previousChangeIter    = -1; // nor the last step's velocity changes and error (A1a): the next step
	stepErrorIter         = -1; // compares with none, and the stepper takes that step's raw error
	lastFilterIter        = -1; // and filters (A1d: the loaded run has no share of a last filter)
	filteredShare         = std::numeric_limits<Real>::quiet_NaN();
	freshPersisting       = std::numeric_limits<Real>::quiet_NaN();
	const auto saved      = Omega::instance().getScene(); // the scene being saved (Engine::scene can be stale)
	noCoefficientChangeAt = saved ? saved->iter : -1;
}

void ViscBridgeImplicitSolver::postLoad(ViscBridgeImplicitSolver&)
{
	static const std::string name = "ViscBridgeImplicitSolver";
	rollback.check(checked(), [&] {
		viscbridge::requireInRange(name, "tolerance", tolerance, 0, true, 1, true);
		viscbridge::requireInRange(name, "maxIterations", maxIterations, 1, false, 1e9, false);
		viscbridge::requireInRange(name, "refreshIterations", refreshIterations, 1, false, 1e9, false);
		viscbridge::parseName(name, "preconditioner", preconditioner, preconditionerNames, "preconditioner");
		viscbridge::requireInRange(name, "factorMemoryLimit", factorMemoryLimit, 0, false, std::numeric_limits<double>::infinity(), true);
	});
}

namespace {
	using Clock  = std::chrono::steady_clock;
	Real seconds(Clock::time_point since) { return std::chrono::duration<Real>(Clock::now() - since).count(); }
}

// The work of the last step's forces, now that Newton has reported the kinetic energy they produced.
void ViscBridgeImplicitSolver::bookPendingWork()
{
	if (!pendingWork) return;
	if (scene->trackEnergy) {
		bookKey(vb::EnergyKey::viscDissipNormal, pendingNormal);
		if (pendingTangentialKeys) {
			bookKey(vb::EnergyKey::viscDissipTangential, pendingTangential);
			bookKey(vb::EnergyKey::viscDissipRotational, pendingRotational);
		}
	}
	pendingWork = false;
}

void ViscBridgeImplicitSolver::bookKey(vb::EnergyKey key, Real value)
{
	const vb::EnergyKeySpec& spec = vb::spec(key);
	scene->energy->add(value, spec.name, energyIndex[static_cast<std::size_t>(key)], spec.reset);
}


void ViscBridgeImplicitSolver::action()
{
	auto phase = Clock::now();
	auto lap   = [&phase](Real& total) {
                total += seconds(phase);
                phase = Clock::now();
	};
	bookPendingWork();
	last                           = sceneAttachment<ViscBridgeImplicitWarmStart>(scene);
	const NewtonIntegrator& newton = checkScene();
	Gathered                g      = gather(newton);
	bridges                        = static_cast<int>(g.system.size());
	if (!distributed::any(scene, !g.system.empty())) { // [MPI] a rank without bridges still takes part while others have some
		iterations = 0;
		residual   = 0;
		return;
	}
	const vb::ImplicitViscousSystem sys(std::move(g.bodies), std::move(g.system), scene->dt);
	Eigen::VectorXd                 x = warmStartGuess(sys, g.ids);
	lap(timeGather);
	const vb::Preconditioner* pre = refreshPreconditioner(sys, g.pattern);
	lap(timeFactorise);
	solve(sys, g.ids, x, pre);
	lap(timeSolve);
	const std::vector<vb::BridgeResistance> R = sys.bridgeForces(x);
	applyForces(sys, g.ids, x, R);
	lap(timeApply);
	bookEnergy(sys, g, x, R);
	lap(timeEnergy);
	if (ViscBridgeContext::hasEngine(scene, "ViscBridgeTimeStepper")) estimateStepError(sys, g, x, R, pre);
	lap(timeEstimate);
}

const NewtonIntegrator& ViscBridgeImplicitSolver::checkScene()
{
	const NewtonIntegrator* newton = nullptr;
	for (const auto& e : scene->engines)
		if (const auto* n = dynamic_cast<const NewtonIntegrator*>(e.get())) newton = n;
	if (!newton) throw std::runtime_error("ViscBridgeImplicitSolver: no NewtonIntegrator in O.engines; the implicit velocities need it.");
	if (newton->damping != 0)
		throw std::invalid_argument(
		        "ViscBridgeImplicitSolver: NewtonIntegrator.damping=" + vb::formatValue(newton->damping)
		        + " is out of range with implicit viscous integration; allowed: 0 (numerical damping would move the velocities off the implicit solution).");
	const size_t signature = sceneSignature(scene);
	if (signature != validatedSignature) { // e.g. a non-dissipative tangential model, or clumps
		validateScene(scene, false);
		validatedSignature = signature;
	}
	return *newton;
}


void ViscBridgeImplicitSolver::solve(const vb::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids, Eigen::VectorXd& x, const vb::Preconditioner* pre)
{
	// [MPI] under yade.mpy: one system over all ranks (CG with the ghosts' velocities exchanged)
	const vb::SolveReport rep = distributed::active(scene) ? solveOverRanks(scene, sys, ids, x, tolerance, maxIterations, pre)
	                                                       : sys.solve(x, tolerance, maxIterations, pre);
	lastIterationsSeen = rep.iterations;
	if (++cycleSolves == 1) freshIterations = rep.iterations;
	cycleIterations += rep.iterations;
	unknowns           = 0;
	for (size_t d = 0; d < sys.size(); ++d)
		unknowns += sys.isFree(d) ? 1 : 0;
	iterations = rep.iterations;
	residual   = rep.residual;
	totalIterations += rep.iterations;
	products += rep.products;
	timeProducts += rep.productSeconds;
	timePreconditioner += rep.preconditionerSeconds;
	++solves;
	if (rep.direct) {
		++fallbacks;
		LOG_WARN("ViscBridgeImplicitSolver: CG did not reach tolerance " << tolerance << " in " << maxIterations << " iterations at step " << scene->iter
		                                                                 << "; solved with the sparse Cholesky fallback (relative residual " << residual << ").");
	}
	if (!rep.converged && distributed::active(scene)) // [MPI] the same on every rank: there is no direct fallback over ranks
		throw std::runtime_error("ViscBridgeImplicitSolver: CG over the " + std::to_string(distributed::ranks(scene)) + " ranks of yade.mpy did not reach tolerance "
		                         + vb::formatValue(tolerance) + " in maxIterations=" + std::to_string(maxIterations) + " at step " + std::to_string(scene->iter)
		                         + " (relative residual " + vb::formatValue(rep.residual) + "); raise ViscBridgeImplicitSolver.maxIterations.");
	if (!rep.converged || !x.allFinite())
		throw std::runtime_error("ViscBridgeImplicitSolver: the implicit viscous system could not be solved at step " + std::to_string(scene->iter)
		                         + " (relative residual " + vb::formatValue(rep.residual) + " after CG and the direct fallback).");
}

// The viscous forces that make NewtonIntegrator land on x: M(x − v)/Δt − F_other on free
// components; on prescribed ones (walls, fixed bodies, blocked DOFs) what the bridges exert.
void ViscBridgeImplicitSolver::applyForces(const vb::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids, const Eigen::VectorXd& x,
                                           const std::vector<vb::BridgeResistance>& R)
{
	const long nBodies = static_cast<long>(ids.size());
	if (warmStart) {
		last->force.resize(scene->bodies->size(), Vector3r::Zero());
		last->torque.resize(scene->bodies->size(), Vector3r::Zero());
	}
	const Real dt = scene->dt;
#pragma omp parallel for schedule(static)
	for (long i = 0; i < nBodies; ++i) {
		const vb::SystemBody& b = sys.bodies()[i];
		Vector3r              f, t; // what the bridges exert: −(D v)
		sys.resultantOn(i, R, f, t);
		f = -f, t = -t;
		if (warmStart) last->force[ids[i]] = f, last->torque[ids[i]] = t;
		const Vector3r momentChange = b.inertia * (x.segment<3>(6 * i + 3) - b.angVel);
		for (int d = 0; d < 3; ++d) {
			if (b.free[d]) f[d] = b.mass * (x[6 * i + d] - b.vel[d]) / dt - b.force[d];
			if (b.free[d + 3]) t[d] = momentChange[d] / dt - b.torque[d];
		}
		scene->forces.addForce(ids[i], f);
		scene->forces.addTorque(ids[i], t);
	}
}

// What each bridge reports, and the work of its forces over the step, from the velocities the step
// started with and the implicit ones it ends with (physics.md §6); booked at the next step.
void ViscBridgeImplicitSolver::bookEnergy(const vb::ImplicitViscousSystem& sys, const Gathered& g, const Eigen::VectorXd& x,
                                          const std::vector<vb::BridgeResistance>& R)
{
	const auto own = distributed::ownership(scene);
	const Real dt  = scene->dt;
	const long m   = static_cast<long>(R.size());
	const Eigen::VectorXd v0 = scene->trackEnergy ? sys.currentVelocities() : Eigen::VectorXd(); // the work needs the step's start
	std::vector<std::array<Real, 3>> work(scene->trackEnergy ? m : 0, { 0, 0, 0 }); // per bridge: normal, sliding, rolling
	std::vector<char>                tangential(work.size(), 0);
#pragma omp parallel for schedule(static)
	for (long k = 0; k < m; ++k) {
		const vb::SystemBridge& c  = sys.bridges()[k];
		const vb::ViscousBlock& bl = c.block;
		ViscBridgePhys&         ph = *g.owners[k];
		auto kinematics = [&](const Eigen::VectorXd& v, Vector3r& u, Vector3r& s) {
			const Vector3r v1 = v.segment<3>(6 * c.body1), w1 = v.segment<3>(6 * c.body1 + 3), v2 = v.segment<3>(6 * c.body2),
			               w2 = v.segment<3>(6 * c.body2 + 3);
			const Vector3r dv = (v1 + w1.cross(bl.r1)) - (v2 + w2.cross(bl.r2) + c.shiftVel);
			const Real     vn = bl.n.dot(dv);
			u                 = dv - vn * bl.n;
			s                 = (bl.a1 * w1 + bl.a2 * w2).cross(bl.n);
			return vn;
		};
		Vector3r   u1, s1, u0, s0;
		const Real vn1 = kinematics(x, u1, s1);
		const Vector3r normal = -bl.cn * vn1 * bl.n;
		ph.normalViscousForce = normal;
		ph.shearViscousForce  = -R[k].force1 - normal;
		ph.normalForce -= normal; // YADE sense (sustained by body 2)
		ph.shearForce -= ph.shearViscousForce;
		if (scene->trackEnergy && own.interaction(*g.described[k], scene)) { // [MPI] a shared bridge is booked by one rank
			tangential[k]            = bl.resistance.m11 != 0 || bl.resistance.m22 != 0;
			const Real vn0           = kinematics(v0, u0, s0);
			const vb::TangentialWork w = vb::tangentialWork(bl.resistance, u1, s1, u0, s0);
			work[k]                  = { bl.cn * vn1 * 0.5 * (vn1 + vn0) * dt, w.sliding * dt, w.rolling * dt };
		}
	}
	Real dissipN = 0, dissipT = 0, dissipR = 0; // summed in the bridges' order: the same on any number of threads
	for (const auto& w : work)
		dissipN += w[0], dissipT += w[1], dissipR += w[2];
	const bool tangentialEffect = std::any_of(tangential.begin(), tangential.end(), [](char t) { return t != 0; });
	if (scene->trackEnergy) {
		pendingNormal         = dissipN;
		pendingTangential     = dissipT;
		pendingRotational     = dissipR;
		pendingTangentialKeys = tangentialEffect;
		pendingWork           = true;
	}
}

} // namespace yade
