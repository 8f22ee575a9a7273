#include "viscbridge/engines/ViscBridgeImplicitSolver.hpp"
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/distributed/ImplicitSolveOverRanks.hpp"
#include "viscbridge/engines/ViscBridgeImplicitWarmStart.hpp"
#include "viscbridge/yade/SceneAttachment.hpp"
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include "viscbridge/core/linalg/ImplicitViscousSystem.hpp"
#include "viscbridge/core/linalg/LaggedPreconditioner.hpp"
#include "viscbridge/core/timestep/AccuracyControl.hpp"
#include "viscbridge/core/util/AvailableMemory.hpp"
#include "viscbridge/core/util/Validation.hpp"
#include "viscbridge/scene/SceneValidation.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include <core/Clump.hpp>
#include <core/Scene.hpp>
#include <pkg/dem/NewtonIntegrator.hpp>
#include <pkg/dem/ScGeom.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <limits>

namespace yade {

CREATE_LOGGER(ViscBridgeImplicitSolver);

void ViscBridgeImplicitSolver::preSave(ViscBridgeImplicitSolver&)
{
	factorisedIter        = -1;
	previousChangeIter    = -1; // nor the last step's velocity changes and error (A1a): the next step
	stepErrorIter         = -1; // compares with none, and the stepper takes that step's raw error
	lastFilterIter        = -1; // and filters (A1d: the loaded run has no share of a last filter)
	filteredShare         = std::numeric_limits<Real>::quiet_NaN();
	const auto saved      = Omega::instance().getScene(); // the scene being saved (Engine::scene can be stale)
	noCoefficientChangeAt = saved ? saved->iter : -1;
}

namespace {
	// the preconditioners, by name: two lagged ones, block Jacobi (not lagged), and the choice
	// between the two lagged ones by the factor's size (the default)
	constexpr std::array<const char*, 4> preconditionerNames { "cholesky", "multigrid", "jacobi", "auto" };
	const std::string                    cholesky = preconditionerNames[0], multigrid = preconditionerNames[1], jacobi = preconditionerNames[2],
	                  automatic = preconditionerNames[3];
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
	namespace vb = viscbridge;
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

struct ViscBridgeImplicitSolver::Gathered {
	std::vector<Interaction*>    described; // the bridges, in the system's order
	std::vector<ViscBridgePhys*> owners;
	std::vector<std::array<Body::id_t, 2>> ends; // their bodies' ids
	std::vector<Body::id_t>      ids; // the system's bodies, ordered by id (same bodies, same system)
	std::vector<vb::SystemBody>  bodies;
	std::vector<vb::SystemBridge> system;
	std::vector<long>            pattern; // bodies with their free components, and bridges (in the interactions' order): decides whether the factor's analysis still holds
};

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

// What the time stepper's estimate needs of this step (physics.md A1a–A1d): the step's error
// filtered twice by its system, and the leapfrog's offsets and the carried errors relaxed once by
// it.  Each filter is one application of the lagged Cholesky factor (or a CG solve with another
// preconditioner); the error's first filter, the offsets and the carried errors share one (a sweep
// over a large factor is memory-bound: four columns cost little more than one).  The offsets and
// the carried errors are checked by one product each and refined by CG where the factor lags this
// step's matrix: a lagged factor would not relax what the bridges' new coefficients relax, and A1b
// and A1c carry on what it keeps (this step's solve taking one iteration does not tell: its warm
// start hides the lag; the stiffening pair's estimate moved 4-fold when the check was skipped on
// it, and a capillary pair whose gap closed 200-fold since the factorisation kept offsets as large
// as its speed, an estimate 850x its true error).  A1d: all of it every errorFilterInterval steps;
// in between, the factor alone relaxes the offsets and the carried errors (their sum checked) and
// filters the step's error once, the second filter taken at the share the last full one kept.
void ViscBridgeImplicitSolver::estimateStepError(const vb::ImplicitViscousSystem& sys, const Gathered& g, const Eigen::VectorXd& x,
                                                 const std::vector<vb::BridgeResistance>& R, const vb::Preconditioner* pre)
{
	const std::vector<Body::id_t>& ids = g.ids;
	Eigen::VectorXd                u, o, carried, fresh;
	const bool                     compare = stepErrorChange(sys, ids, x, u);
	const bool                     full    = filterIsDue(compare && !u.isZero(0));
	const bool                     relax   = offsetsOf(ids, sys.size(), o);
	const bool                     carry   = carriedErrorsOf(sys, g, x, R, carried, fresh);
	stepErrorCovered.assign(scene->bodies->size(), 0);
	stepErrorSq = stepCarriedSq = 0;
	stepErrorIter               = -1;
	if (full) lastFilterIter = scene->iter, ++estimateFilters;
	// the columns: [u] [o] [carried fresh], filtered together with the factor
	const long      atO = long(compare), atCarried = atO + long(relax), columns = atCarried + 2 * long(carry);
	const bool      factor = pre && preconditionerInUse == cholesky;
	Eigen::MatrixXd in(sys.size(), columns), out;
	if (columns > 0) {
		if (compare) in.col(0) = u;
		if (relax) in.col(atO) = o;
		if (carry) in.col(atCarried) = carried, in.col(atCarried + 1) = fresh;
		if (factor) sys.filterColumns(in, out, 1e-3, 100, pre, true);
		else filteredApart(sys, in, out, atCarried, pre);
	}
	for (long c = atO; c < columns && factor && full; ++c) { // CG from the factor's answer: one product where it holds
		Eigen::VectorXd y = out.col(c);
		sys.filter(in.col(c), y, 1e-2, 100, pre, false);
		out.col(c) = y;
	}
	if (relax) storeRelaxed(ids, out.col(atO), ViscBridgeContext::of(scene).velocityOffset);
	if (carry) {
		Eigen::VectorXd relaxed = out.col(atCarried) + out.col(atCarried + 1);
		if (factor && !full) // between filters their sum alone is checked: a factor of a stiffer network over-relaxes it
			sys.filter(in.col(atCarried) + in.col(atCarried + 1), relaxed, 1e-2, 100, pre, false);
		storeCarried(ids, relaxed);
	}
	if (!compare) return;
	Real onceSq = 0; // Σ m|Fu|²
	for (size_t i = 0; i < ids.size(); ++i) {
		const auto at = 6 * static_cast<long>(i);
		onceSq += sys.bodies()[i].mass * out.col(0).segment<3>(at).squaredNorm();
		// the step's own share of A1c apart: it is what a smaller step makes smaller (the controller's
		// measure, A4), while the error carried from earlier steps is made
		if (carry)
			stepCarriedSq += sys.bodies()[i].mass
			        * std::pow(vb::persistingShare(in.col(atCarried + 1).segment<3>(at).norm(), out.col(atCarried + 1).segment<3>(at).norm()), 2);
		stepErrorCovered[ids[i]] = 1;
	}
	stepErrorIter = scene->iter;
	if (!full) {
		stepErrorSq = onceSq > 0 ? filteredShare * onceSq : 0;
		return;
	}
	u.setZero();
	for (size_t i = 0; i < ids.size(); ++i) // the second filter takes the translations only, as the first
		u.segment<3>(6 * static_cast<long>(i)) = out.col(0).segment<3>(6 * static_cast<long>(i));
	Eigen::VectorXd filtered;
	sys.filter(u, filtered, 1e-3, 100, pre, factor);
	for (size_t i = 0; i < ids.size(); ++i)
		stepErrorSq += sys.bodies()[i].mass * filtered.segment<3>(6 * static_cast<long>(i)).squaredNorm();
	filteredShare = onceSq > 0 ? stepErrorSq / onceSq : std::numeric_limits<Real>::quiet_NaN();
}

// A1d: a filter is due every errorFilterInterval steps (the time stepper's choice), where the last
// one's share is not known for the error this step has, and at a step whose Δt moved by more than 1 %
// from the last one's: the offsets (A1b) it makes need this step's matrix, not only the lagged
// factor (a capillary pair whose Δt grew, test_accuracy: 3× its estimate at a constant Δt).
bool ViscBridgeImplicitSolver::filterIsDue(bool stepErrorNow)
{
	const int  interval = ViscBridgeContext::of(scene).errorFilterInterval;
	const bool dtMoved  = !(std::abs(scene->dt - lastEstimatedDt) <= 0.01 * scene->dt);
	lastEstimatedDt     = scene->dt;
	return interval <= 1 || lastFilterIter < 0 || scene->iter - lastFilterIter >= interval || (stepErrorNow && !std::isfinite(filteredShare)) || dtMoved;
}

// Without the factor, each column by CG: the step's error and the offsets (the columns before
// `carriedFrom`) to 10⁻³, the carried errors to 10⁻² (an estimate of what an error does next).
void ViscBridgeImplicitSolver::filteredApart(const vb::ImplicitViscousSystem& sys, const Eigen::MatrixXd& in, Eigen::MatrixXd& out, long carriedFrom,
                                             const vb::Preconditioner* pre)
{
	out.resize(in.rows(), in.cols());
	Eigen::MatrixXd part;
	sys.filterColumns(in.leftCols(carriedFrom), part, 1e-3, 100, pre, false);
	out.leftCols(carriedFrom) = part;
	sys.filterColumns(in.rightCols(in.cols() - carriedFrom), part, 1e-2, 100, pre, false);
	out.rightCols(in.cols() - carriedFrom) = part;
}

// A1c: the scheme holds each bridge's coefficients over a step in which they change (a gap that
// closes stiffens its bridge, P4): against the trapezoidal companion the step gives the bodies
// ½Δt (D_{n+1} − D_n) v too much impulse — with the slope of the last change, (Δt_n/Δt_{n−1})(D_n −
// D_{n−1}).  Unlike A1a's error it is not a transient the relaxation absorbs: what (M + Δt D)⁻¹ does
// not give the velocity it gives the position, the body relaxing to a shifted place.  So it is
// carried, with the position error ξ it makes: a gap wrong by δS = n·(ξ₂ − ξ₁) gives the bridge the
// normal coefficient of that gap, C^n + (ΔC^n/ΔS) δS by the last change over the gap change ΔS (a
// bridge that keeps stiffening shrinks the error in proportion: R1's w₀ − A ln(S₀/S)).  Per body
// `carried` = ε + (the wrong gap's impulse)/m and `fresh` = (this step's trapezoidal impulse)/m, which
// the caller relaxes through the system with the offsets, ε_{n+1} = (M + Δt D)⁻¹ M (carried + fresh),
// then ξ_{n+1} = ξ_n + Δt ε_{n+1}.  A bridge formed since the last step is a jump of the model (A1),
// not a change.  False if nothing is carried.  [MPI] not over ranks, as the offsets.
bool ViscBridgeImplicitSolver::carriedErrorsOf(const vb::ImplicitViscousSystem& sys, const Gathered& g, const Eigen::VectorXd& x,
                                               const std::vector<vb::BridgeResistance>& R, Eigen::VectorXd& carried, Eigen::VectorXd& fresh)
{
	auto&          context = ViscBridgeContext::of(scene);
	const long     m = static_cast<long>(sys.bridges().size()), n = static_cast<long>(g.ids.size());
	const Real     dt        = scene->dt;
	const Vector3r unstarted = Vector3r::Constant(std::numeric_limits<Real>::quiet_NaN());
	carried.setZero(static_cast<long>(sys.size()));
	fresh.setZero(static_cast<long>(sys.size()));
	context.velocityError.resize(scene->bodies->size(), unstarted);
	context.positionError.resize(scene->bodies->size(), unstarted);
	if (distributed::active(scene)) return false;
	for (const Body::id_t id : g.ids)
		if (!context.velocityError[id].allFinite() || !context.positionError[id].allFinite())
			context.velocityError[id] = context.positionError[id] = Vector3r::Zero();
	const vb::BridgeResistance        none { Vector3r::Zero(), Vector3r::Zero(), Vector3r::Zero(), Vector3r::Zero() };
	std::vector<vb::BridgeResistance> step(static_cast<size_t>(m), none), wrongGap(static_cast<size_t>(m), none);
	const auto scaled = [](const vb::BridgeResistance& a, const vb::BridgeResistance& b, Real w) {
		return vb::BridgeResistance { w * (a.force1 - b.force1), w * (a.torque1 - b.torque1), w * (a.force2 - b.force2), w * (a.torque2 - b.torque2) };
	};
	bool any = false;
#pragma omp parallel for schedule(static) reduction(|| : any)
	for (long k = 0; k < m; ++k) {
		const vb::SystemBridge& c   = sys.bridges()[k];
		ViscBridgePhys&         ph  = *g.owners[k];
		const Real              gap = -static_cast<const ScGeom&>(*g.described[k]->geom).penetrationDepth;
		if (ph.solvedIter == scene->iter - 1 && ph.solvedDt > 0 && scene->iter != noCoefficientChangeAt) {
			const vb::BridgeResistance before = vb::bridgeResistance(ph.solvedBlock, x.segment<3>(6 * c.body1), x.segment<3>(6 * c.body1 + 3),
			                                                          x.segment<3>(6 * c.body2), x.segment<3>(6 * c.body2 + 3), c.shiftVel);
			const Real gapChange = gap - ph.solvedGap;
			const Real gapError  = c.block.n.dot(context.positionError[g.ids[c.body2]] - context.positionError[g.ids[c.body1]]);
			step[k]              = scaled(R[k], before, 0.5 * dt * dt / ph.solvedDt); // the trapezoid's share
			// what the wrong gap changes: the normal coefficient's slope over the last change (none from a
			// gap that barely moved: a slope of round-off), on the normal motion it resists
			if (std::abs(gapChange) > 1e-6 * std::abs(gap)) {
				const Vector3r dv = x.segment<3>(6 * c.body1) - x.segment<3>(6 * c.body2) - c.shiftVel;
				const Vector3r f  = -dt * (c.block.cn - ph.solvedBlock.cn) / gapChange * gapError * c.block.n.dot(dv) * c.block.n;
				wrongGap[k]       = { f, Vector3r::Zero(), Vector3r(-f), Vector3r::Zero() };
			}
			any = true;
		}
		ph.solvedBlock = c.block, ph.solvedIter = scene->iter, ph.solvedDt = dt, ph.solvedGap = gap;
	}
#pragma omp parallel for schedule(static) reduction(|| : any)
	for (long i = 0; i < n; ++i) {
		const Vector3r& was = context.velocityError[g.ids[i]];
		if (!(sys.bodies()[i].mass > 0)) continue; // a wall or a fixed body: no velocity to be wrong
		Vector3r        f, t;
		sys.resultantOn(i, wrongGap, f, t); // in the order of the body's bridges: the same sum on any number of threads
		carried.segment<3>(6 * i) = was + f / sys.bodies()[i].mass;
		sys.resultantOn(i, step, f, t);
		fresh.segment<3>(6 * i) = f / sys.bodies()[i].mass;
		any                     = any || !was.isZero(0);
	}
	return any;
}

// A1b: the offsets of the bodies this step holds, in the system's layout (translations); false if
// none has one.  [MPI] not over ranks: there the offsets stay as they are (larger).
bool ViscBridgeImplicitSolver::offsetsOf(const std::vector<Body::id_t>& ids, size_t size, Eigen::VectorXd& o)
{
	const auto& offset = ViscBridgeContext::of(scene).velocityOffset;
	o.setZero(static_cast<long>(size));
	if (distributed::active(scene)) return false;
	bool any = false;
	for (size_t i = 0; i < ids.size(); ++i)
		if (static_cast<size_t>(ids[i]) < offset.size() && offset[ids[i]].allFinite())
			o.segment<3>(6 * static_cast<long>(i)) = offset[ids[i]], any = true;
	return any;
}

// A1c: the carried velocity errors relaxed by the step, and the positions they move.
void ViscBridgeImplicitSolver::storeCarried(const std::vector<Body::id_t>& ids, const Eigen::VectorXd& relaxed)
{
	auto& context = ViscBridgeContext::of(scene);
	storeRelaxed(ids, relaxed, context.velocityError);
	for (const Body::id_t id : ids)
		context.positionError[id] = ViscBridgeContext::relaxedOffset(context.positionError[id] + scene->dt * context.velocityError[id]);
}

// A1b, A1c: the offsets and the carried errors relax through the bridges as a velocity does,
// (M + Δt D)⁻¹M o: what a cluster moving as one carries stays, a relative part decays.
void ViscBridgeImplicitSolver::storeRelaxed(const std::vector<Body::id_t>& ids, const Eigen::VectorXd& relaxed, std::vector<Vector3r>& perBody)
{
	for (size_t i = 0; i < ids.size(); ++i)
		if (static_cast<size_t>(ids[i]) < perBody.size() && perBody[ids[i]].allFinite())
			perBody[ids[i]] = ViscBridgeContext::relaxedOffset(relaxed.segment<3>(6 * static_cast<long>(i)));
}

// A1a: the error of this step against its trapezoidal companion is ½Δt_n times the change of the
// mean acceleration, ½Δt_n(Δv_n/Δt_n − Δv_{n−1}/Δt_{n−1}) (per body: a force that changes over the
// step, the viscous one included) — per unit time, so that the controller's change of Δt, which
// changes Δv with it, is not taken for an error.  Backward Euler follows that only as far as
// (M + Δt D)⁻¹ M lets it: filtered twice by this step's matrix — the filtered estimate of stiff
// solvers, which scales like the true error both where Δt·C/m is small (z²/2) and large (1/z), so
// that the stiff relaxations of the network do not count as errors while its soft, collective
// motions do.  With the Cholesky factor, which the refresh rule keeps within a few CG iterations of
// exact, each filter is one application of it (an estimate needs no more: bench/accuracy_target.py
// keeps its calibration); otherwise CG with this step's preconditioner to a loose tolerance.
bool ViscBridgeImplicitSolver::stepErrorChange(const vb::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids, const Eigen::VectorXd& x,
                                               Eigen::VectorXd& u)
{
	const size_t          n     = scene->bodies->size();
	static const Vector3r none   = Vector3r::Constant(std::numeric_limits<Real>::quiet_NaN()); // not solved in that step
	static const Vector3r jumped = Vector3r::Constant(std::numeric_limits<Real>::infinity());  // a jump of the model
	const bool            valid  = previousChange.size() == n && previousChangeIter == scene->iter - 1 && !distributed::active(scene);
	const Real            dt    = scene->dt;
	stepChange.assign(n, none);
	u.setZero(static_cast<long>(sys.size()));
	for (size_t i = 0; i < ids.size(); ++i) {
		stepChange[ids[i]]  = (x.segment<3>(6 * static_cast<long>(i)) - sys.bodies()[i].vel) / dt;
		const Vector3r& was = valid ? previousChange[ids[i]] : none;
		if (was.allFinite()) u.segment<3>(6 * static_cast<long>(i)) = 0.5 * dt * (stepChange[ids[i]] - was);
		else if (!std::isinf(was[0])) stepChange[ids[i]] = jumped; // its first solved step (below)
	}
	// a bridge that formed this step, or a body solved for the first time (its bridges formed under
	// the explicit scheme, or the scheme just switched), changed the model at once: the body's change
	// of velocity in this step is the model's jump, not one the next step's trapezoidal companion
	// should compare to (the stepper's raw estimate skips a formation step the same way, A1)
	for (const BridgeEvent& e : ViscBridgeContext::of(scene).events(scene->iter))
		if (e.kind == BridgeEvent::Kind::formed)
			for (Body::id_t id : { e.id1, e.id2 })
				if (static_cast<size_t>(id) < n) stepChange[id] = jumped;
	previousChange.swap(stepChange);
	previousChangeIter = scene->iter;
	return valid;
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

// The bridges the law described this step, in the interactions' order: tested on all threads
// (following the pointers to each interaction and its physics is the cost), collected in order.
void ViscBridgeImplicitSolver::describedBridges(Gathered& g) const
{
	InteractionContainer&                    all     = *scene->interactions; // (its size() is not const)
	const long                               n       = static_cast<long>(all.size());
	const int                                vbIndex = ViscBridgePhys::getClassIndexStatic();
	const long                               iter    = scene->iter;
	bridgeOf.assign(n, nullptr);
	endsOf.resize(n); // read only where bridgeOf is set
#pragma omp parallel for schedule(static)
	for (long k = 0; k < n; ++k) {
		const Interaction& I = *all[k];
		if (!I.isReal() || I.phys->getClassIndex() != vbIndex) continue;
		auto* ph = static_cast<ViscBridgePhys*>(I.phys.get());
		if (ph->bridge && ph->implicitBlock.valid && ph->implicitBlockIter == iter) bridgeOf[k] = ph, endsOf[k] = { I.getId1(), I.getId2() };
	}
	for (long k = 0; k < n; ++k)
		if (bridgeOf[k]) {
			g.described.push_back(all[k].get());
			g.owners.push_back(bridgeOf[k]);
			g.ends.push_back(endsOf[k]);
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

// The lagged preconditioner, recomputed when the bridges or free components changed, when a refresh
// pays (renewal: the last solve's iterations c_T reach the cycle's average cost per step
// (refreshCost + Σ c_i)/T, which a later refresh could only raise while the iterations grow), or
// when the last solve needed more than refreshIterations iterations.  The Cholesky analysis is kept
// if only the numbers changed.
const vb::Preconditioner* ViscBridgeImplicitSolver::refreshPreconditioner(const vb::ImplicitViscousSystem& sys, const std::vector<long>& pattern)
{
	const std::string kind = sys.size() == 0 ? jacobi : preconditioner == automatic ? automaticKind(sys) : preconditioner;
	if (kind == jacobi) {
		preconditionerInUse = kind;
		factorKind          = "";
		return nullptr;
	}
	if (kind != preconditionerInUse) factorisation.reset();
	preconditionerInUse = kind;
	// The same bodies and bridges: usually in the same order as at the factorisation (YADE reorders its
	// interactions only when some are erased), else the same set once sorted.
	std::vector<long> sorted;
	auto              sortedPattern = [&]() -> const std::vector<long>& {
                if (sorted.empty()) {
                        sorted = pattern;
                        std::sort(sorted.begin(), sorted.end());
                }
                return sorted;
	};
	const bool samePattern = factorisation && factorisation->matches(sys.size()) && (pattern == factorisedOrder || sortedPattern() == factorisedPattern);
	// The multigrid of the same unknowns stays a valid preconditioner when bridges form or rupture (the
	// Cholesky factor's analysis must match the couplings, so it is redone).
	const bool sameUnknowns = samePattern
	        || (kind == multigrid && factorisation && factorisation->matches(sys.size())
	            && std::equal(pattern.begin(), pattern.begin() + sys.bodies().size(), factorisedOrder.begin(), factorisedOrder.begin() + sys.bodies().size()));
	const bool pays = cycleSolves > 0 && static_cast<double>(lastIterationsSeen) * cycleSolves >= refreshCost + cycleIterations;
	// refreshIterations counts beyond what a fresh multigrid needs (tens of iterations; the factor: one or two)
	const int cap = refreshIterations + (kind == multigrid ? freshIterations : 0);
	if (sameUnknowns && !pays && lastIterationsSeen <= cap && factorisedIter >= 0) return factorisation.get();
	if (!refreshLagged(sys, samePattern)) {
		factorisation.reset(); // not positive definite: CG with block Jacobi, then the fallback
		factorisedPattern.clear();
		factorisedOrder.clear();
		preconditionerInUse = jacobi;
		factorKind          = "";
		return nullptr;
	}
	factorisedPattern = sortedPattern();
	factorisedOrder   = pattern;
	factorisedIter    = scene->iter;
	factorBlocks      = static_cast<long>(factorisation->storedBlocks());
	levels            = factorisation->levels();
	factorKind        = factorisation->factorKind();
	refreshCost       = factorisation->refreshCost(sys.bridges().size());
	cycleSolves = cycleIterations = 0;
	++factorisations;
	return factorisation.get();
}

// 'auto' keeps the multigrid it chose while the bed has about the bodies and bridges of that choice
// (within a quarter: a new analysis costs about a factorisation); otherwise it tries the factor.
std::string ViscBridgeImplicitSolver::automaticKind(const vb::ImplicitViscousSystem& sys) const
{
	auto near = [](size_t now, size_t then) { return 4 * std::max(now, then) <= 5 * std::min(now, then); };
	const bool keep = preconditionerInUse == multigrid && factorisation && near(sys.size(), chosenUnknowns) && near(sys.bridges().size(), chosenBridges);
	return keep ? multigrid : cholesky;
}

// The preconditioner of kind preconditionerInUse recomputed; the Cholesky factor analysed first, so
// that 'auto' takes the multigrid instead when the factor would not fit in factorMemoryLimit: the
// factor is the faster of the two at every size measured, 10³–10⁵ bodies, and the solver's peak
// memory was 1.5× its factor's at 10⁵ (docs/performance.md §3).  False: not positive definite.
bool ViscBridgeImplicitSolver::refreshLagged(const vb::ImplicitViscousSystem& sys, bool samePattern)
{
	if (preconditionerInUse == multigrid) {
		if (!factorisation) factorisation = boost::make_shared<vb::LaggedMultigrid>();
		return factorisation->refresh(sys, samePattern);
	}
	if (!factorisation) factorisation = boost::make_shared<vb::LaggedCholesky>();
	auto& factor = static_cast<vb::LaggedCholesky&>(*factorisation);
	factor.analyse(sys, samePattern);
	factorBytes = static_cast<Real>(factor.factorBytes());
	const Real limit = factorMemoryLimit > 0 ? factorMemoryLimit : 0.5 * static_cast<Real>(vb::availableMemoryBytes());
	if (preconditioner != automatic || factorBytes <= limit) return factor.factorise();
	LOG_INFO("preconditioner='auto': the Cholesky factor of " << sys.bodies().size() << " bodies would take " << factorBytes / 1e9 << " GB (limit "
	                                                          << limit / 1e9 << " GB); the multigrid takes its place");
	preconditionerInUse = multigrid;
	chosenUnknowns      = sys.size();
	chosenBridges       = sys.bridges().size();
	factorisation       = boost::make_shared<vb::LaggedMultigrid>();
	return factorisation->refresh(sys, false);
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
