#include "viscbridge/engines/ViscBridgeTimeStepper.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include "viscbridge/scene/SceneValidation.hpp"
#include "viscbridge/core/timestep/NetworkSpectrum.hpp"
#include "viscbridge/core/timestep/TimeStepBounds.hpp"
#include "viscbridge/core/util/Validation.hpp"
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/scene/NetworkOverRanks.hpp"
#include <algorithm>
#include <limits>
#include <numeric>

namespace yade {

namespace vb = viscbridge;

CREATE_LOGGER(ViscBridgeTimeStepper);

void ViscBridgeTimeStepper::postLoad(ViscBridgeTimeStepper&)
{
	static const std::string name = "ViscBridgeTimeStepper";
	rollback.check(checked(), [&] {
		viscbridge::requireInRange(name, "safety", safety, 0, true, 1, false);
		viscbridge::requireInRange(name, "maxGrowth", maxGrowth, 1, false, std::numeric_limits<double>::max(), false);
		viscbridge::requireInRange(name, "rayleighFraction", rayleighFraction, 0, true, 1, false);
		viscbridge::requireNonNegative(name, "maxDt", maxDt, " [s]; 0 means no limit");
		viscbridge::requireInRange(name, "tolerance", tolerance, 0, true, 0.1, false);
		viscbridge::requireInRange(name, "maxIterations", maxIterations, 1, false, 1e6, false);
		viscbridge::requireInRange(name, "maxInterval", maxInterval, 1, false, 1e9, false);
		if (accuracy != 0 && !(accuracy > 0 && accuracy < 1)) viscbridge::rejectValue(name, "accuracy", accuracy, "(0, 1), or 0 for none");
		viscbridge::requireInRange(name, "implicitCost", implicitCost, 1, false, 1e6, false);
		viscbridge::requireInRange(name, "errorFilterInterval", errorFilterInterval, 1, false, 1e6, false);
	});
	restoreSavedState();
}

bool ViscBridgeTimeStepper::isActivated()
{
	// timeStepUpdateInterval is inherited, without a hook on assignment, so it is checked here.  The
	// stepper runs every step whatever it says (it corrects dt at once for the bridges that form
	// between full updates: skipping steps let a new bridge run at the dry dt, a blow-up at the first
	// bridge); a value above 1 — a habit from GlobalStiffnessTimeStepper scripts — caps the steps
	// between full updates instead (fullUpdateCap).  0 would divide by zero in YADE's base class.
	if (timeStepUpdateInterval == 0)
		viscbridge::rejectValue("ViscBridgeTimeStepper", "timeStepUpdateInterval", 0.0,
		                        ">= 1 (the most steps between full updates; the stepper still corrects dt every step)");
	return active;
}

int ViscBridgeTimeStepper::fullUpdateCap() const
{
	// YADE's default 1 leaves the interval to maxInterval; a larger value caps it
	return timeStepUpdateInterval > 1 ? std::min<int>(maxInterval, static_cast<int>(std::min<unsigned>(timeStepUpdateInterval, 1000000000u)))
	                                  : maxInterval;
}

bool ViscBridgeTimeStepper::viscousImplicit() const { return viscousIntegrationIsImplicit(scene); }

Real ViscBridgeTimeStepper::limitNow() const
{
	// both are below the true limit: the corrected spectral estimate, and P14 (rigorous)
	return std::max(viscbridge::networkLimit(modeD + addedD, modeK + addedK), hP14);
}

void ViscBridgeTimeStepper::fullUpdate(Scene* sc)
{
	const bool implicit = viscousImplicit();
	bound.evaluate(sc, implicit, rayleighFraction);
	agreeOnBounds(sc); // [MPI] the smallest over the ranks
	network.gather(sc, !implicit);
	// when most of the network is new since the last update (a bed wetted after loading, a sudden
	// impact), the last mode says nothing about the new one, and a start from it can settle on a
	// lesser mode: start cold, from the largest diagonal entries
	if (2 * distributed::sum(sc, Real(changedBodies.size())) > distributed::sum(sc, Real(network.idOf.size()))) modeById.clear();
	viscbridge::VecX mode;
	network.modeFromIds(modeById, mode);
	// where bridges formed since the last update, a new stiffest mode may be: into the start
	std::vector<std::size_t> candidates;
	for (Body::id_t id : changedBodies)
		if (static_cast<size_t>(id) < network.compactOf.size() && network.compactOf[id] >= 0)
			for (int d = 0; d < 3; ++d) candidates.push_back(6 * network.compactOf[id] + d);
	changedBodies.clear();
	// [MPI] under yade.mpy all ranks iterate together on the whole network (NetworkOverRanks.hpp)
	viscbridge::StabilityEstimate e;
	if (distributed::active(sc)) {
		const NetworkOverRanks overRanks(sc, network);
		e    = viscbridge::stabilityLimit(overRanks, mode, tolerance, maxIterations, candidates);
		mode = overRanks.ownPart(mode); // so that the critical bodies named are this rank's own
	} else
		e = viscbridge::stabilityLimit(network.op, mode, tolerance, maxIterations, candidates);
	network.modeToIds(mode, modeById);
	// the quotients scaled up by the residual: networkLimit of them is h/(1 + ‖r‖/θ) (P18)
	modeD = e.d * (1 + e.residual), modeK = e.k * (1 + e.residual);
	hP14  = bound.network;
	addedD = addedK = 0;
	addedDamping.assign(sc->bodies->size(), 0);
	addedStiffness.assign(sc->bodies->size(), 0);
	const Real h = limitNow();
	// the interval grows while the limit stays put and shrinks when it moves
	if (hAtUpdate > 0 && std::isfinite(h) && std::isfinite(hAtUpdate)) {
		const Real change = std::abs(h - hAtUpdate) / hAtUpdate;
		if (change < 0.01) updateInterval = std::min(2 * updateInterval, fullUpdateCap());
		else if (change > 0.05) updateInterval = std::max(updateInterval / 2, 1);
	}
	hAtUpdate      = h;
	lastUpdateIter = sc->iter;
	iterations     = e.iterations;
	residual       = e.residual;
	++updates;
	modeDamping    = e.d;
	modeStiffness  = e.k;
	dtRitz         = safety * e.h;
	describeMode();
}

ViscBridgeTimeStepper::FormedBridge ViscBridgeTimeStepper::formedRecord(Body::id_t id1, Body::id_t id2, const ViscBridgePhys& ph)
{
	return { id1, id2, ph.stepDampingRate(), ph.stepStiffnessRate() };
}

void ViscBridgeTimeStepper::addFormedBridges(Scene* sc)
{
	// The bridges that formed in this step's interaction loop, as the law published them, with the
	// coefficients their physics holds now.  In the stepper's first step (after its creation or after
	// loading) the full update that follows sees them all.
	std::vector<FormedBridge> formed;
	if (listening)
		for (const BridgeEvent& e : ViscBridgeContext::of(sc).events(sc->iter)) {
			// from the physics, not the event: ViscBridgeLiquid (before this engine) may have changed a
			// film bridge's volume, hence its capillary stiffness, since the law published it
			if (e.kind != BridgeEvent::Kind::formed) continue;
			const shared_ptr<Interaction>& I = sc->interactions->find(e.id1, e.id2);
			if (!I || !I->isReal()) continue;
			if (const auto* ph = dynamic_cast<const ViscBridgePhys*>(I->phys.get())) formed.push_back(formedRecord(e.id1, e.id2, *ph));
		}
	listening = true;
	correctForFormed(sc, formed);
}

void ViscBridgeTimeStepper::correctForFormed(Scene* sc, const std::vector<FormedBridge>& formed)
{
	const bool implicit = viscousImplicit();
	for (const auto& f : formed) {
		const Real d = implicit ? 0 : f.damping, k = f.stiffness;
		for (Body::id_t id : { f.id1, f.id2 }) {
			const shared_ptr<Body>& b = Body::byId(id, sc);
			if (!b || !b->isDynamic() || static_cast<size_t>(id) >= addedDamping.size()) continue;
			// a body is a candidate once (their number, not the order they formed in, sets the start)
			if (addedDamping[id] == 0 && addedStiffness[id] == 0 && (d > 0 || k > 0)) changedBodies.push_back(id);
			addedDamping[id] += d, addedStiffness[id] += k;
			// Weyl: the top eigenvalue grows by at most the largest row sum the new pairs add
			addedD = std::max(addedD, addedDamping[id]), addedK = std::max(addedK, addedStiffness[id]);
			hP14   = std::min(hP14, bound.bodyLimit(id, addedDamping[id], addedStiffness[id]));
		}
	}
}

void ViscBridgeTimeStepper::describeMode()
{
	std::vector<std::pair<Real, Body::id_t>> share;
	Real                                     total = 0;
	for (std::size_t i = 0; i < modeById.size(); ++i) {
		const Real s = modeById[i].squaredNorm();
		if (s > 0) share.push_back({ s, static_cast<Body::id_t>(i) }), total += s;
	}
	std::sort(share.begin(), share.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
	criticalBodies.clear();
	criticalShare = share.empty() ? 0 : share.front().first;
	Real carried = 0;
	for (const auto& s : share) {
		if (carried >= 0.9 * total || criticalBodies.size() >= 10) break;
		criticalBodies.push_back(s.second);
		carried += s.first;
	}
}

Real ViscBridgeTimeStepper::exactLimit()
{
	NetworkOfScene now;
	now.gather(scene, !viscousImplicit());
	return viscbridge::denseStabilityLimit(now.op);
}

void ViscBridgeTimeStepper::computeTimeStep(Scene* sc)
{
	const size_t signature = sceneSignature(sc);
	const bool   changed   = signature != validatedSignature;
	// [MPI] under yade.mpy a rank's invalid body stops every rank (none is left waiting below)
	distributed::collectively(sc, [&] {
		if (changed) { // e.g. a sphere of radius 0 would give dt = 0 or NaN
			validateScene(sc, false);
			validatedSignature = signature;
		}
		if (accuracy > 0) refuseAccuracyOverRanks(sc);
	});
	const Real accuracyLimit = accuracyStep(sc); // the last step's error, before anything changes dt
	const bool due = lastUpdateIter < 0 || sc->iter - lastUpdateIter >= std::min(updateInterval, fullUpdateCap());
	addFormedBridges(sc);
	// a scene just loaded has new engine objects (a new signature) but the saved state is its own
	bool anyChanged = changed && !resumesSavedState(sc);
	agreeOnChanges(sc, anyChanged); // [MPI] a change anywhere and the corrections of all ranks
	// a full update when due, or when the new bridges moved the limit: look again
	if (anyChanged || due || limitNow() < 0.9 * hAtUpdate) fullUpdate(sc);
	const Real network = limitNow(), h = std::min(network, bound.rayleigh);
	dtNetwork   = safety * network;
	dtP14       = safety * hP14;
	dtBound     = safety * h;
	dtCollision = safety * bound.collision;
	dtViscous   = modeD > 0 ? safety * 2 / modeD : std::numeric_limits<Real>::infinity();
	errorBound  = dtRitz > 0 && std::isfinite(dtRitz) ? std::max<Real>(0, (dtRitz - dtNetwork) / dtRitz) : 0;
	if (bound.rayleigh <= network) {
		governing    = "rayleigh";
		criticalBody = bound.rayleighBody;
	} else {
		// which term of P18 dominates the top mode at its limit: the damping's 2h·d or the stiffness' h²·k
		governing    = 2 * network * modeD >= network * network * modeK ? "viscous-network" : "collision";
		criticalBody = !criticalBodies.empty() ? criticalBodies.front() : bound.criticalBody;
	}
	agreeWithOtherRanks(sc); // [MPI] the smallest limit of all ranks, the same dt on all of them
	// before a step is known (or from dt = 0, which nothing can grow from): the first step of A4
	const bool firstStep       = !accuracyEstimate.started() || !(sc->dt > 0);
	const Real accuracyStepNow = accuracy > 0 && firstStep ? vb::AccuracyEstimate::firstStep(dtBound, accuracy) : accuracyLimit;
	if (accuracyStepNow < dtBound) governing = "accuracy";
	chooseScheme(sc, accuracyLimit);
	Real dt = std::min(dtBound, accuracyStepNow);
	if (maxDt > 0) dt = std::min(dt, maxDt);
	// A1d: the solver filters the estimate every step while the controller holds dt or is within 4×
	// of it (between filters, its step error follows the raw error at the last filter's share)
	ViscBridgeContext::of(sc).errorFilterInterval = accuracy > 0 && !(accuracyStepNow >= 4 * dt) ? 1 : errorFilterInterval;
	ViscBridgeContext::of(sc).controllerReadsFreshError = accuracy > 0;
	if (!std::isfinite(dt)) return; // nothing to bound (no dynamic spheres, no contacts): keep dt
	if (!(dt > 0))
		throw std::runtime_error("ViscBridgeTimeStepper: the time-step bound is " + viscbridge::formatValue(dt) + " s at body #"
		                         + std::to_string(criticalBody) + "; check its radius, mass and material (all must be > 0 and finite).");
	// growth is limited from a valid previous step only (O.dt <= 0 would otherwise stay there), and
	// not at the first step of another scheme (its limit is a new one, computed at this step)
	const bool newScheme = lastSwitchIter >= 0 && lastSwitchIter == sc->iter - 1;
	// with a tolerance, the controller sets the pace of growth (A4)
	const Real growth = accuracy > 0 ? std::max(maxGrowth, vb::AccuracyEstimate::growth) : maxGrowth;
	const Real before = sc->dt;
	sc->dt            = sc->dt > 0 && !newScheme ? std::min(dt, growth * sc->dt) : dt;
	advanceOffsets(sc, before);
}

} // namespace yade
