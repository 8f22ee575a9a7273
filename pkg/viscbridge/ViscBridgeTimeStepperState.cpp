// What a saved scene needs to resume exactly: the stepper's state between full updates (the warm
// start, the corrections for bridges formed since, the bounds of the last evaluation), packed into
// the hidden attribute savedState when saving and unpacked when loading. Without it a loaded scene
// would start the mode iteration afresh and take a dt that differs within the tolerance.
#include "ViscBridgeTimeStepper.hpp"
#include <boost/functional/hash.hpp>
#include <core/Omega.hpp>
#include <stdexcept>

namespace yade {

namespace {
	constexpr Real stateLayout = 2; // bump when the packing below changes

	// What the saved state belongs to: the same step, bodies, masses and interactions. A scene loaded
	// and then changed (interactions cleared, bodies added or resized) gets a fresh full update.
	size_t stateSignature(const Scene* scene)
	{
		size_t h = 0;
		boost::hash_combine(h, scene->iter);
		boost::hash_combine(h, scene->bodies->size());
		boost::hash_combine(h, scene->materials.size());
		boost::hash_combine(h, scene->interactions->size());
		for (const auto& b : *scene->bodies)
			if (b) boost::hash_combine(h, b->state->mass);
		return h;
	}
	// a 64-bit signature in two doubles, exactly
	void packSignature(std::vector<Real>& out, size_t s) { out.push_back(Real(s >> 32)), out.push_back(Real(s & 0xffffffffULL)); }

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
}

void ViscBridgeTimeStepper::reset()
{
	modeById.clear(), addedDamping.clear(), addedStiffness.clear(), changedBodies.clear();
	modeD = modeK = hP14 = hAtUpdate = addedD = addedK = criticalShare = 0;
	lastUpdateIter   = -1;
	resumedSignature = 0;
	validatedSignature = 0;
	bound = NetworkTimeStepBound();
}

bool ViscBridgeTimeStepper::resumesSavedState(const Scene* sc)
{
	const bool resumes = resumedSignature != 0 && resumedSignature == stateSignature(sc);
	resumedSignature   = 0;
	return resumes;
}

void ViscBridgeTimeStepper::postSave(ViscBridgeTimeStepper&) { savedState.clear(); }

void ViscBridgeTimeStepper::restoreSavedState()
{
	if (savedState.empty()) return; // not loading (an attribute set from Python), or a fresh stepper
	Reader r { savedState };
	if (r.next() != stateLayout) throw std::runtime_error("ViscBridgeTimeStepper.savedState: saved by another version of ViscBridge");
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
	resumedSignature = (static_cast<size_t>(r.next()) << 32) | static_cast<size_t>(r.next());
	savedState.clear();
}

} // namespace yade
