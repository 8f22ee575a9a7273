// What a saved scene needs to resume exactly: the stepper's state between full updates (the warm
// start, the corrections for bridges formed since, the bounds of the last evaluation), packed into
// the hidden attribute savedState when saving and unpacked when loading. Without it a loaded scene
// would start the mode iteration afresh and take a dt that differs within the tolerance.
//
// The state holds for the network it was computed on: the saved bridges, each with its viscous and
// capillary coefficients.  A bridge the loaded scene has beyond them — formed in the first step
// after loading, when the stepper does not take the law's bridge events yet, or re-created by the user (e.g. the
// interactions cleared and the liquid changed) — enters as a formation, with the same correction
// the law's report would have given; a scene of another step, other bodies or another integration
// gets a fresh full update.
#include "viscbridge/engines/ViscBridgeTimeStepper.hpp"
#include "viscbridge/scene/SceneValidation.hpp"
#include "viscbridge/yade/SceneAttachment.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include <boost/functional/hash.hpp>
#include <core/Omega.hpp>
#include <algorithm>
#include <limits>
#include <stdexcept>

namespace yade {

namespace {
	constexpr Real accuracyTrailer = -25; // marks the accuracy trailer (a count or signature is never negative)
	constexpr Real stateLayout = 4; // bump when the packing below changes (2: without the bridges; 3: the signature counted the interactions)

	// What the saved state belongs to: the same step, bodies, masses and integration (the bridges are
	// compared one by one).  Not the interactions' count: YADE does not save the collider's potential
	// interactions, so a loaded scene has fewer (layout 3 counted them, and a scene saved with some
	// resumed with a fresh update: a dt 1e-8 off the continued run's, found by tools/campaign.py).
	size_t stateSignature(const Scene* scene, bool countInteractions = false)
	{
		size_t h = 0;
		boost::hash_combine(h, scene->iter);
		boost::hash_combine(h, scene->bodies->size());
		boost::hash_combine(h, scene->materials.size());
		if (countInteractions) boost::hash_combine(h, scene->interactions->size());
		boost::hash_combine(h, viscousIntegrationIsImplicit(scene));
		for (const auto& b : *scene->bodies)
			if (b) boost::hash_combine(h, b->state->mass);
		return h;
	}

	// A bridge as the time step sees it: its bodies and its P14 coefficients (rebuilt identically
	// when a scene is loaded).
	size_t bridgeKey(const Interaction& I, const ViscBridgePhys& ph)
	{
		size_t h = 0;
		boost::hash_combine(h, std::min(I.getId1(), I.getId2()));
		boost::hash_combine(h, std::max(I.getId1(), I.getId2()));
		boost::hash_combine(h, ph.viscousStepCoefficient);
		boost::hash_combine(h, ph.capillaryStiffness);
		return h;
	}

	// Calls f(interaction, physics) for every live bridge of the scene.
	template <class F> void forEachBridge(const Scene* scene, F f)
	{
		const int vbIndex = ViscBridgePhys::getClassIndexStatic();
		for (const auto& I : *scene->interactions)
			if (I->isReal() && I->phys->getClassIndex() == vbIndex) {
				const auto& ph = static_cast<const ViscBridgePhys&>(*I->phys);
				if (ph.bridge) f(*I, ph);
			}
	}

	std::vector<size_t> bridgeKeys(const Scene* scene)
	{
		std::vector<size_t> keys;
		forEachBridge(scene, [&](const Interaction& I, const ViscBridgePhys& ph) { keys.push_back(bridgeKey(I, ph)); });
		std::sort(keys.begin(), keys.end());
		return keys;
	}

	// a 64-bit value in two doubles, exactly
	void   packSignature(std::vector<Real>& out, size_t s) { out.push_back(Real(s >> 32)), out.push_back(Real(s & 0xffffffffULL)); }
	size_t unpackSignature(Real high, Real low) { return (static_cast<size_t>(high) << 32) | static_cast<size_t>(low); }

	template <class T> void pack(std::vector<Real>& out, const std::vector<T>& v)
	{
		out.push_back(static_cast<Real>(v.size()));
		for (const T& x : v) out.push_back(static_cast<Real>(x));
	}

	struct Reader {
		const std::vector<Real>& in;
		size_t                   at = 0;
		Real                     next()
		{
			if (at >= in.size()) throw std::runtime_error("ViscBridgeTimeStepper.savedState: truncated (the saved scene is damaged)");
			return in[at++];
		}
		template <class T> void unpack(std::vector<T>& v)
		{
			v.resize(static_cast<size_t>(next()));
			for (T& x : v) x = static_cast<T>(next());
		}
	};
}

void ViscBridgeTimeStepper::preSave(ViscBridgeTimeStepper&)
{
	savedState = { stateLayout, modeD, modeK, hP14, hAtUpdate, addedD, addedK, static_cast<Real>(lastUpdateIter), criticalShare,
		       bound.collision, bound.viscous, bound.combined, bound.network, static_cast<Real>(bound.criticalBody),
		       bound.rayleigh, bound.rayleighFractionUsed, static_cast<Real>(bound.rayleighBody), static_cast<Real>(bound.rayleighSignature) };
	std::vector<Real> mode;
	for (const auto& m : modeById) mode.insert(mode.end(), m.data(), m.data() + 6);
	pack(savedState, mode);
	pack(savedState, addedDamping);
	pack(savedState, addedStiffness);
	pack(savedState, changedBodies);
	pack(savedState, bound.summed);
	// the scene being saved is Omega's (Engine::scene can be stale for an engine not yet run in it)
	const Scene* saved = Omega::instance().getScene().get();
	packSignature(savedState, saved && lastUpdateIter >= 0 ? stateSignature(saved) : 0);
	const std::vector<size_t> bridges = saved ? bridgeKeys(saved) : std::vector<size_t>();
	savedState.push_back(static_cast<Real>(bridges.size()));
	for (const size_t key : bridges) packSignature(savedState, key);
	// the accuracy settings and the run's error sums (A2), a trailer older scenes do not have: the
	// attributes themselves are not serialised, so that scenes saved before them keep loading
	savedState.insert(savedState.end(), { accuracyTrailer, accuracy, Real(autoIntegration), implicitCost, Real(schemeSwitches) });
	double sums[viscbridge::AccuracyEstimate::stateSize];
	accuracyEstimate.save(sums);
	savedState.insert(savedState.end(), sums, sums + viscbridge::AccuracyEstimate::stateSize);
	// and what the next step's estimate starts from: the forces of the last step (A1) and the
	// leapfrog's offsets (A1b), (id, F, o) of the bodies that have both (older scenes end here; read
	// where the scene has them: saving must not add a context to the scene it is writing)
	const auto        context = saved ? existingAttachment<ViscBridgeContext>(saved) : nullptr;
	std::vector<Real> motion;
	const size_t      counted = context ? std::min(context->velocityOffset.size(), previousForce.size()) : 0;
	for (size_t id = 0; id < counted; ++id) {
		const Vector3r &f = previousForce[id], &o = context->velocityOffset[id];
		if (f.allFinite() && o.allFinite()) motion.insert(motion.end(), { Real(id), f[0], f[1], f[2], o[0], o[1], o[2] });
	}
	savedState.push_back(Real(forceIter));
	pack(savedState, motion);
	// the carried velocity and position errors (A1c), (id, ε, ξ) of the bodies that have them (older
	// scenes end here)
	packPairs(savedState, context ? &context->velocityError : nullptr, context ? &context->positionError : nullptr, counted);
	// the scheme autoIntegration chose (A5): the law of the loaded scene runs it from its first step,
	// before the stepper (older scenes end here; their law's integration held the choice)
	savedState.push_back(Real(chosenScheme));
	savedState.push_back(Real(errorFilterInterval)); // A1d (older scenes end here: the default)
	// the history's error and what the next step takes into it (A1e), (id, ε_h, Fu) of the bodies
	// that have them (older scenes end here: none)
	packPairs(savedState, context ? &context->historyError : nullptr, context ? &context->historyFresh : nullptr, counted);
	// the controller's tightening by the accumulated error (A4c; older scenes end here: none)
	double controller[viscbridge::AccuracyEstimate::controllerStateSize];
	accuracyEstimate.saveController(controller);
	savedState.insert(savedState.end(), controller, controller + viscbridge::AccuracyEstimate::controllerStateSize);
}

// (id, a, b) of the counted bodies that have both vectors, packed (resumePairs reads them back).
void ViscBridgeTimeStepper::packPairs(std::vector<Real>& out, const std::vector<Vector3r>* a, const std::vector<Vector3r>* b, size_t counted) const
{
	std::vector<Real> records;
	const size_t      n = a && b ? std::min({ a->size(), b->size(), counted }) : 0;
	for (size_t id = 0; id < n; ++id) {
		const Vector3r &x = (*a)[id], &y = (*b)[id];
		if (previousForce[id].allFinite() && x.allFinite() && y.allFinite()) records.insert(records.end(), { Real(id), x[0], x[1], x[2], y[0], y[1], y[2] });
	}
	pack(out, records);
}

void ViscBridgeTimeStepper::reset()
{
	modeById.clear(), addedDamping.clear(), addedStiffness.clear(), changedBodies.clear();
	modeD = modeK = hP14 = hAtUpdate = addedD = addedK = criticalShare = 0;
	lastUpdateIter   = -1;
	resumedSignature = 0;
	savedBridges.clear();
	validatedSignature = 0;
	bound = NetworkTimeStepBound();
}

bool ViscBridgeTimeStepper::resumesSavedState(Scene* sc)
{
	const bool resumes = resumedSignature != 0 && resumedSignature == stateSignature(sc, resumedCountsInteractions);
	resumedSignature   = 0;
	if (resumes) { // the bridges the saved state does not know, as formations
		std::vector<FormedBridge> unknown;
		forEachBridge(sc, [&](const Interaction& I, const ViscBridgePhys& ph) {
			if (!std::binary_search(savedBridges.begin(), savedBridges.end(), bridgeKey(I, ph)))
				unknown.push_back(formedRecord(I.getId1(), I.getId2(), ph));
		});
		correctForFormed(sc, unknown);
	}
	std::vector<size_t>().swap(savedBridges);
	return resumes;
}

void ViscBridgeTimeStepper::postSave(ViscBridgeTimeStepper&) { savedState.clear(); }

// The last step's forces as they were saved (the offsets wait for the scene: resumeOffsets).
void ViscBridgeTimeStepper::resumeForces()
{
	const auto none = Vector3r::Constant(std::numeric_limits<Real>::quiet_NaN());
	previousForce.clear();
	for (size_t k = 0; k + savedMotionStride <= resumedMotion.size(); k += savedMotionStride) {
		const auto id = static_cast<size_t>(resumedMotion[k]);
		previousForce.resize(std::max(previousForce.size(), id + 1), none);
		previousForce[id] = resumedVector(resumedMotion, k + 1);
	}
}

void ViscBridgeTimeStepper::restoreSavedState()
{
	if (savedState.empty()) return; // not loading (an attribute set from Python), or a fresh stepper
	Reader r { savedState };
	const Real layout = r.next();
	if (layout != stateLayout && layout != 3) { // an earlier layout: a fresh full update at the first step
		savedState.clear();
		return;
	}
	resumedCountsInteractions = layout == 3; // the same packing, another signature
	modeD = r.next(), modeK = r.next(), hP14 = r.next(), hAtUpdate = r.next(), addedD = r.next(), addedK = r.next();
	lastUpdateIter = static_cast<long>(r.next()), criticalShare = r.next();
	bound.collision = r.next(), bound.viscous = r.next(), bound.combined = r.next(), bound.network = r.next();
	bound.criticalBody = static_cast<Body::id_t>(r.next());
	bound.rayleigh = r.next(), bound.rayleighFractionUsed = r.next(), bound.rayleighBody = static_cast<Body::id_t>(r.next());
	bound.rayleighSignature = static_cast<long>(r.next());
	std::vector<Real> mode;
	r.unpack(mode);
	modeById.resize(mode.size() / 6);
	for (size_t i = 0; i < modeById.size(); ++i) modeById[i] = Eigen::Map<const viscbridge::Vec6>(&mode[6 * i]);
	r.unpack(addedDamping);
	r.unpack(addedStiffness);
	r.unpack(changedBodies);
	r.unpack(bound.summed);
	const Real high = r.next();
	resumedSignature = unpackSignature(high, r.next());
	savedBridges.resize(static_cast<size_t>(r.next()));
	for (size_t& key : savedBridges) {
		const Real h = r.next();
		key          = unpackSignature(h, r.next());
	}
	if (r.at < savedState.size() && savedState[r.at] == accuracyTrailer) {
		r.next();
		accuracy = r.next(), autoIntegration = r.next() != 0, implicitCost = r.next(), schemeSwitches = static_cast<long>(r.next());
		double sums[viscbridge::AccuracyEstimate::stateSize];
		for (double& x : sums) x = r.next();
		accuracyEstimate.restore(sums);
		rollback.keep(checked());
		if (r.at < savedState.size()) {
			forceIter = static_cast<long>(r.next());
			r.unpack(resumedMotion);
			resumeForces();
			if (r.at < savedState.size()) r.unpack(resumedErrors);
			if (r.at < savedState.size()) chosenScheme = static_cast<int>(r.next());
			if (r.at < savedState.size()) errorFilterInterval = std::max(1, static_cast<int>(r.next())), rollback.keep(checked());
			if (r.at < savedState.size()) r.unpack(resumedHistory);
			if (r.at + viscbridge::AccuracyEstimate::controllerStateSize <= savedState.size()) {
				double controller[viscbridge::AccuracyEstimate::controllerStateSize];
				for (double& x : controller) x = r.next();
				accuracyEstimate.restoreController(controller);
			}
		}
	}
	savedState.clear();
}

} // namespace yade
