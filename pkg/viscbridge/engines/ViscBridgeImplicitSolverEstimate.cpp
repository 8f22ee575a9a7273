// ViscBridgeImplicitSolver: what the time stepper's error estimate needs of a step (physics.md
// A1a–A1e): the step's error filtered, the offsets, carried errors and the velocity history's error
// relaxed by the step's system.
#include "viscbridge/engines/ViscBridgeImplicitSolverGathered.hpp"
#include "viscbridge/core/timestep/AccuracyControl.hpp"
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include <core/Scene.hpp>
#include <pkg/dem/ScGeom.hpp>
#include <algorithm>
#include <limits>
#include <numeric>

namespace yade {

using namespace implicit_solver;

// What the time stepper's estimate needs of this step (physics.md A1a–A1e): the step's error
// filtered twice by its system, and the leapfrog's offsets, the carried errors and the history's
// error relaxed once by it (at a jump of the model, the step's error is its own: stepErrorOf).
// Each filter is one application of the lagged Cholesky factor (or a CG solve with another
// preconditioner); the error's first filter, the offsets, the history and the carried errors share
// one (one sweep for several columns costs less than a sweep each: five took 2.7 single sweeps' time
// on the 300-sphere settling bed).  The offsets, the history and the carried errors are checked by
// one product each and refined by CG where the factor lags this step's matrix: a lagged factor
// would not relax what the bridges' new coefficients relax, and A1b and A1c carry on what it keeps
// (this step's solve taking one iteration does not tell: its warm start hides the lag; the
// stiffening pair's estimate moved 4-fold when the check was skipped on it, and a capillary pair
// whose gap closed 200-fold since the factorisation kept offsets as large as its speed, an
// estimate 850x its true error).  A1d: all of it every errorFilterInterval steps; in between, the
// factor alone relaxes the offsets and the carried errors (their sum checked; without a tolerance
// in one column, the persisting share of their step part taken at the one the last full filter
// found) and filters the step's error once, the second filter taken at the share it kept.
void ViscBridgeImplicitSolver::estimateStepError(const vb::ImplicitViscousSystem& sys, const Gathered& g, const Eigen::VectorXd& x,
                                                 const std::vector<vb::BridgeResistance>& R, const vb::Preconditioner* pre)
{
	const std::vector<Body::id_t>& ids = g.ids;
	Eigen::VectorXd                u, o, h, carried, fresh;
	const bool                     estimated = stepErrorOf(sys, ids, x, u);
	const bool                     relax     = offsetsOf(ids, sys.size(), o);
	const bool                     history   = historyOf(ids, sys.size(), h);
	const bool                     carry     = carriedErrorsOf(sys, g, x, R, carried, fresh);
	Real                           freshSq   = 0; // Σ m|fresh|²
	for (size_t i = 0; i < ids.size() && carry; ++i)
		freshSq += sys.bodies()[i].mass * fresh.segment<3>(6 * static_cast<long>(i)).squaredNorm();
	// the step part's persisting share at the last full filter's serves stepError alone: the
	// controller (a tolerance) needs this step's (a capillary pair's controlled run took 20× the
	// steps with the share)
	const bool shared = !ViscBridgeContext::of(scene).controllerReadsFreshError;
	const bool full   = filterIsDue(estimated && !u.isZero(0), shared && freshSq > 0);
	stepErrorCovered.assign(scene->bodies->size(), 0);
	stepErrorSq = stepCarriedSq = 0;
	stepErrorIter               = -1;
	if (full) lastFilterIter = scene->iter, ++estimateFilters;
	// the columns: [u] [o] [h] [carried fresh], filtered together with the factor; between full
	// filters, where the share serves, the carried errors' two columns are one, their sum (A1d)
	const long atO = long(estimated), atH = atO + long(relax), atCarried = atH + long(history);
	const bool merged         = shared && !full;
	const long carriedColumns = carry ? (merged ? 1 : 2) : 0, columns = atCarried + carriedColumns;
	const bool      factor = pre && preconditionerInUse == cholesky;
	Eigen::MatrixXd in(sys.size(), columns), out;
	if (columns > 0) {
		if (estimated) in.col(0) = u;
		if (relax) in.col(atO) = o;
		if (history) in.col(atH) = h;
		if (carriedColumns == 2) in.col(atCarried) = carried, in.col(atCarried + 1) = fresh;
		if (carriedColumns == 1) in.col(atCarried) = carried + fresh;
		if (factor) sys.filterColumns(in, out, 1e-3, 100, pre, true);
		else filteredApart(sys, in, out, atCarried, pre);
	}
	// at full filters, CG from the factor's answer (one product where it holds) for the offsets, the
	// history and, where the controller reads the step part, each carried column; else their sum below
	const long checkedUpTo = !full ? atO : shared ? atCarried : columns;
	for (long c = atO; c < checkedUpTo && factor; ++c) {
		Eigen::VectorXd y = out.col(c);
		sys.filter(in.col(c), y, 1e-2, 100, pre, false);
		out.col(c) = y;
	}
	if (relax) storeRelaxed(ids, out.col(atO), ViscBridgeContext::of(scene).velocityOffset);
	if (estimated) storeHistory(ids, history ? Eigen::VectorXd(out.col(atH)) : h, out.col(0));
	if (carry) {
		Eigen::VectorXd relaxed = out.col(atCarried);
		if (carriedColumns == 2) relaxed += out.col(atCarried + 1);
		if (factor && checkedUpTo < columns) // their sum checked: a factor of a stiffer network over-relaxes it
			sys.filter(carried + fresh, relaxed, 1e-2, 100, pre, false);
		storeCarried(ids, relaxed);
	}
	if (!estimated) return;
	Real onceSq = 0; // Σ m|Fu|²
	for (size_t i = 0; i < ids.size(); ++i) {
		const auto at = 6 * static_cast<long>(i);
		const Real m  = sys.bodies()[i].mass;
		onceSq += m * out.col(0).segment<3>(at).squaredNorm();
		// the step's own share of A1c apart: it is what a smaller step makes smaller (the controller's
		// measure, A4), while the error carried from earlier steps is made; between full filters at
		// the share of the fresh error the last one found persisting (A1d)
		if (carry && !merged)
			stepCarriedSq += m * std::pow(vb::persistingShare(fresh.segment<3>(at).norm(), out.col(atCarried + 1).segment<3>(at).norm()), 2);
		stepErrorCovered[ids[i]] = 1;
	}
	if (!merged && freshSq > 0) freshPersisting = stepCarriedSq / freshSq;
	if (merged && freshSq > 0) stepCarriedSq = freshPersisting * freshSq;
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
// one's share is not known for the error this step has (A1a's second filter, the persisting share
// of A1c's step part), and at a step whose Δt moved by more than 1 % from the last one's: the
// offsets (A1b) it makes need this step's matrix, not only the lagged factor (a capillary pair
// whose Δt grew, test_accuracy: 3× its estimate at a constant Δt).
bool ViscBridgeImplicitSolver::filterIsDue(bool stepErrorNow, bool freshNow)
{
	const int  interval = ViscBridgeContext::of(scene).errorFilterInterval;
	const bool dtMoved  = !(std::abs(scene->dt - lastEstimatedDt) <= 0.01 * scene->dt);
	lastEstimatedDt     = scene->dt;
	const bool noShare  = (stepErrorNow && !std::isfinite(filteredShare)) || (freshNow && !std::isfinite(freshPersisting));
	return interval <= 1 || lastFilterIter < 0 || scene->iter - lastFilterIter >= interval || noShare || dtMoved;
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

// A1e: the history's error and the last step's once-filtered error it takes in, in the system's
// layout (translations), ε_h + F u_{n−1}: relaxed by this step, Fε_h + F²u_{n−1} (A1a's error of the
// last step, one step late); false if none has one.  [MPI] not over ranks, as the offsets.
bool ViscBridgeImplicitSolver::historyOf(const std::vector<Body::id_t>& ids, size_t size, Eigen::VectorXd& h)
{
	const auto& context = ViscBridgeContext::of(scene);
	h.setZero(static_cast<long>(size));
	if (distributed::active(scene)) return false;
	bool       any   = false;
	const auto entry = [](const std::vector<Vector3r>& v, Body::id_t id) {
		return static_cast<size_t>(id) < v.size() && v[id].allFinite() ? v[id] : Vector3r::Zero();
	};
	for (size_t i = 0; i < ids.size(); ++i) {
		const Vector3r e = entry(context.historyError, ids[i]) + entry(context.historyFresh, ids[i]);
		if (!e.isZero(0)) h.segment<3>(6 * static_cast<long>(i)) = e, any = true;
	}
	return any;
}

// A1e: the relaxed history error of this step's bodies, and the error this step filtered once
// (`once`), which the next step takes in.
void ViscBridgeImplicitSolver::storeHistory(const std::vector<Body::id_t>& ids, const Eigen::VectorXd& relaxed, const Eigen::VectorXd& once)
{
	auto&          context = ViscBridgeContext::of(scene);
	const size_t   n       = scene->bodies->size();
	const Vector3r unstarted = Vector3r::Constant(std::numeric_limits<Real>::quiet_NaN());
	historyWork.assign(n, unstarted); // a body that leaves the system leaves its history (it rejoins at a jump)
	context.historyFresh.assign(n, unstarted);
	for (size_t i = 0; i < ids.size(); ++i) {
		const auto at = 6 * static_cast<long>(i);
		historyWork[ids[i]]          = ViscBridgeContext::relaxedOffset(relaxed.segment<3>(at));
		context.historyFresh[ids[i]] = once.segment<3>(at);
	}
	context.historyError.swap(historyWork);
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
// changes Δv with it, is not taken for an error; at a jump of the model (and the step after it) the
// step's own error instead (jumpStepError).  Backward Euler follows that only as far as
// (M + Δt D)⁻¹ M lets it: filtered twice by this step's matrix — the filtered estimate of stiff
// solvers, which scales like the true error both where Δt·C/m is small (z²/2) and large (1/z), so
// that the stiff relaxations of the network do not count as errors while its soft, collective
// motions do.  With the Cholesky factor, which the refresh rule keeps within a few CG iterations of
// exact, each filter is one application of it (an estimate needs no more: bench/accuracy_target.py
// keeps its calibration); otherwise CG with this step's preconditioner to a loose tolerance.
// False under MPI (not over ranks: the offsets, carried errors and history are not either).
bool ViscBridgeImplicitSolver::stepErrorOf(const vb::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids, const Eigen::VectorXd& x,
                                           Eigen::VectorXd& u)
{
	const size_t          n     = scene->bodies->size();
	static const Vector3r none  = Vector3r::Constant(std::numeric_limits<Real>::quiet_NaN()); // not solved in that step
	const bool            valid = previousChange.size() == n && previousJumped.size() == n && previousChangeIter == scene->iter - 1;
	const Real            dt    = scene->dt;
	u.setZero(static_cast<long>(sys.size()));
	if (distributed::active(scene)) return false;
	const std::vector<char> jumped = jumpedBodies(sys, ids, valid);
	stepChange.assign(n, none);
	stepJumped.assign(n, 0);
	previousJumped.resize(n, 0);
	std::vector<char> uncompared(ids.size(), 0); // this step is a jump, or follows one
	bool              anyUncompared = false;
	for (size_t i = 0; i < ids.size(); ++i) {
		const Body::id_t id = ids[i];
		stepChange[id]      = (x.segment<3>(6 * static_cast<long>(i)) - sys.bodies()[i].vel) / dt;
		stepJumped[id]      = jumped[i];
		uncompared[i]       = jumped[i] || previousJumped[id];
		anyUncompared       = anyUncompared || uncompared[i];
		if (!uncompared[i]) u.segment<3>(6 * static_cast<long>(i)) = 0.5 * dt * (stepChange[id] - previousChange[id]);
	}
	if (anyUncompared) jumpStepError(sys, ids, x, uncompared, u);
	previousChange.swap(stepChange);
	previousJumped.swap(stepJumped);
	previousChangeIter = scene->iter;
	return true;
}

// A1e: where a step is a jump of the model, or follows one, the two steps' changes tell nothing of
// its error; the step's own does: against its trapezoidal companion the scheme gives the bodies an
// impulse ½Δt D (v_n − v_{n+1}) too much on the viscous forces of the step (a decay's first steps,
// where its speed and its error are largest).  In the history's column, for those bodies.
void ViscBridgeImplicitSolver::jumpStepError(const vb::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids, const Eigen::VectorXd& x,
                                             const std::vector<char>& uncompared, Eigen::VectorXd& u) const
{
	const Eigen::VectorXd d = x - sys.currentVelocities();
	Eigen::VectorXd       y;
	sys.apply(d, y, false); // M d + Δt D d
	for (size_t i = 0; i < ids.size(); ++i) {
		const auto  at = 6 * static_cast<long>(i);
		const Real  m  = sys.bodies()[i].mass;
		if (!uncompared[i] || !(m > 0)) continue;
		// all six components: M⁻¹D d has none in the modes the bridges do not damp, its translations alone would
		const Matrix3r& I = sys.bodies()[i].inertia;
		u.segment<3>(at) = -0.5 * (y.segment<3>(at) - m * d.segment<3>(at)) / m;
		if (I.trace() > 0) u.segment<3>(at + 3) = -0.5 * I.ldlt().solve(Vector3r(y.segment<3>(at + 3) - I * d.segment<3>(at + 3)));
	}
}

// A1: a bridge that formed or ruptured this step, or a body solved for the first time (its bridges
// formed under the explicit scheme, or the scheme just switched), changed the model at once — and
// with it the velocity change of every body the bridges tie to it (the solve moves a cluster as
// one).  Such a change is the model's jump, not one the step integrated: neither this step nor the
// next compares with it.  Skipping both keeps the history (A1e) whole: summed, the steps' changes
// telescope, and with only one of the two skipped the jump itself would stay in the history for
// good where the bridges do not relax it (a cluster's common motion).  Per body of the system.
std::vector<char> ViscBridgeImplicitSolver::jumpedBodies(const vb::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids, bool valid) const
{
	std::vector<long> root(ids.size());
	std::iota(root.begin(), root.end(), 0);
	const auto find = [&](long i) {
		while (root[i] != i) i = root[i] = root[root[i]];
		return i;
	};
	for (const vb::SystemBridge& c : sys.bridges()) // walls and fixed bodies tie nothing together
		if (sys.bodies()[c.body1].mass > 0 && sys.bodies()[c.body2].mass > 0) root[find(c.body1)] = find(c.body2);
	std::vector<char> jumped(ids.size(), 0);
	const auto        mark = [&](Body::id_t id) {
		const auto at = std::lower_bound(ids.begin(), ids.end(), id);
		if (at != ids.end() && *at == id) jumped[find(at - ids.begin())] = 1;
	};
	for (size_t i = 0; i < ids.size(); ++i)
		if (!valid || !previousChange[ids[i]].allFinite()) mark(ids[i]);
	for (const BridgeEvent& e : ViscBridgeContext::of(scene).events(scene->iter))
		mark(e.id1), mark(e.id2);
	for (size_t i = 0; i < ids.size(); ++i)
		jumped[i] = jumped[find(static_cast<long>(i))];
	return jumped;
}

} // namespace yade
