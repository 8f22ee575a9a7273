// ViscBridgeContext: what the ViscBridge functors and engines of one scene share.
//
// Engines never include or cast to each other's classes; what one tells another goes through
// here (docs/architecture.md, "Channels"):
//   - errors found where nothing can be thrown (inside InteractionLoop's parallel loop), raised by
//     ViscBridgeGuard at the start of the next step;
//   - the work of the conservative bridge forces (capillary, physics.md P21), booked by the law with
//     or without energy tracking, counted by the guard as energy put in;
//   - bridge events: the law publishes every formation and rupture of a bridge into per-thread
//     queues; any engine that runs after InteractionLoop reads the step's events in one order,
//     sorted by bodies, whatever the number of threads.
//
// One context lives in each scene, in Scene::miscParams (created on first use, gone with the
// scene; nothing of it is saved: a loaded scene starts with an empty one).
#pragma once
#include "viscbridge/yade/BridgeEvent.hpp"
#include "viscbridge/yade/ContactForce.hpp"
#include <core/Scene.hpp>
#include <lib/base/openmp-accu.hpp>
#include <lib/serialization/Serializable.hpp>
#include <atomic>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace yade {

class ViscBridgeContext : public Serializable {
	// events: one queue per thread for the step `publishedIter`, merged once into `merged`
	std::vector<std::vector<BridgeEvent>> queues;
	std::vector<BridgeEvent>              merged;
	// contact forces: one queue per thread for the step `publishedIter`, ordered once into `ordered`
	std::vector<std::vector<ContactForce>>       forceQueues;
	std::vector<const ContactForce*>             ordered;
	std::vector<size_t>                          firstOf, placed; // the counting sort's workspace
	long                                         orderedIter = -1;
	long                                  publishedIter = -1, mergedIter = -1;
	bool                                  forcesKept = false; // in step publishedIter
	// The step whose loop pass is open, -1 when none: from the law's first contact of a step until an
	// engine reads what the pass produced.  YADE repeats a step that threw with the same iter (its
	// Scene::moveToNextTimeStep advances iter only at the end), so a pass already read is over and the
	// repeated step begins a new one instead of adding to the failed step's forces and events.
	std::atomic<long>                     openPassIter { -1 };
	void                                  closePass() { openPassIter.store(-1, std::memory_order_relaxed); }
	std::string                           pendingError;
	std::mutex                            pendingMutex;
	std::set<std::string>                 warned; // the plausibility warnings said in this scene
	// this thread's queue of a per-thread set (sized by beginStep)
	template <class T> static std::vector<T>& ownQueue(std::vector<std::vector<T>>& perThread)
	{
#ifdef YADE_OPENMP
		return perThread[omp_get_thread_num()];
#else
		return perThread[0];
#endif
	}

public:
	// The scene's context, created in scene->miscParams on first use.  Not thread-safe: called from
	// engines (serial) or, inside InteractionLoop, once per step under a critical section (see the law).
	static ViscBridgeContext&        of(Scene* scene);
	static shared_ptr<ViscBridgeContext> shared(Scene* scene); // the same, held

	// Whether O.engines has an engine of class `className` (by name: engines never know each other's classes).
	static bool hasEngine(const Scene* scene, const std::string& className);
	// Whether O.engines has a live engine of class `className` after the first InteractionLoop and
	// before the first NewtonIntegrator (where an engine that sums or reads the loop's forces belongs).
	static bool hasEngineAfterLoop(const Scene* scene, const std::string& className);
	// The gravity NewtonIntegrator adds (zero without one).
	static Vector3r newtonGravity(const Scene* scene);
	// The first engine of O.engines that implements interface `Interface` (declared in this layer), or null.
	template <class Interface> static const Interface* findEngine(const Scene* scene)
	{
		for (const auto& e : scene->engines)
			if (const auto* found = dynamic_cast<const Interface*>(e.get())) return found;
		return nullptr;
	}

	// Errors found where nothing can be thrown: the first one is raised by ViscBridgeGuard at the start
	// of the next step (a guard is added to O.engines for this if there is none).
	void        raiseAtNextStep(Scene* scene, const std::string& message);
	std::string takePendingError();

	// A warning about a value no wet granulation run uses (a likely unit mistake), said once per
	// scene and `key` through YADE's log; the run goes on.  warnCurrent: the same for O's scene (Python).
	void        warnOnce(const std::string& key, const std::string& message);
	static void warnCurrent(const std::string& key, const std::string& message);

	// Work of the conservative bridge forces (capillary) since the context was created, as booked:
	// −work, the sign of a dissipation (physics.md P21).
	OpenMPAccumulator<Real> conservativeWork;

	// [accuracy] Per body id, the velocity offset of the leapfrog's position update (physics.md A1b):
	// ViscBridgeTimeStepper adds ½(Δt_new − Δt_old)·a when it changes Δt (NaN: not started), the
	// implicit solver lets the bridges relax it as they relax any velocity.
	std::vector<Vector3r> velocityOffset;
	// [accuracy] Per body id, the velocity and position errors the change of its bridges' coefficients
	// left (physics.md A1c): the implicit solver adds each step's, relaxes the velocity error through
	// the bridges as an offset and moves the position error by Δt times it; under the explicit scheme
	// the time stepper carries a damped body's step error through the bridges' live coefficients,
	// as explicit Euler carries a velocity (NaN: not started).
	std::vector<Vector3r> velocityError, positionError;
	// [accuracy] Per body id, the error of the velocity history the implicit scheme's own steps made
	// (physics.md A1e): each step's filtered error (A1a) carried through the bridges, (M + Δt D)⁻¹M,
	// as the velocity it is an error of relaxes; and the last step's error once filtered, which the
	// next step's relaxation takes in (NaN: not started).
	std::vector<Vector3r> historyError, historyFresh;
	// [accuracy] Steps between the implicit solver's full filters of the estimate (physics.md A1d),
	// set by the time stepper each step: 1 while its accuracy controller holds Δt.
	int errorFilterInterval = 1;
	// [accuracy] Whether the time stepper's accuracy controller reads the step's own part of the
	// carried errors (A4: with a tolerance); else only stepError shows it, and the solver may take it
	// at the last full filter's share between full filters (A1d).
	bool controllerReadsFreshError = true;
	// An offset relaxed step after step decays towards subnormal numbers, which slow every sweep of
	// the factor that relaxes it ~10× (measured: 4 applications' time on the settling bench); far
	// below any velocity a run resolves, it is none.
	static Vector3r relaxedOffset(const Vector3r& o) { return o.cwiseAbs().maxCoeff() < 1e-100 ? Vector3r::Zero() : o; }

	// Events.  beginStep() must run once per loop pass before the first publish() (the law does it
	// under its per-step critical section, whenever passOpen(iter) is false); publish() is then safe
	// from any thread.  `keepsForces`: the law keeps every wet contact's forces this step (keepForce),
	// for ViscBridgeForceSum.
	void beginStep(long iter, bool keepsForces = false);
	bool passOpen(long iter) const { return openPassIter.load(std::memory_order_acquire) == iter; }
	void publish(const BridgeEvent& event);
	// The forces of a wet contact this step, for ViscBridgeForceSum (the law calls it only while one
	// is in place); safe from any thread, as publish().
	void keepForce(const ContactForce& force);
	// The forces kept in step `iter` (empty if none), sorted by (smaller id, larger id): the same
	// sequence on any number of threads.  `bodies`: the scene's number of bodies (ids below it).
	// For engines that run after InteractionLoop.
	const std::vector<const ContactForce*>& forces(long iter, size_t bodies);
	// Whether forces(iter, …) lists every wet contact of step `iter` (the law kept them all).
	bool keptEveryContact(long iter)
	{
		closePass();
		return publishedIter == iter && forcesKept;
	}
	// The events of step `iter` (empty if none were published in it), sorted by (id1, id2, kind):
	// the same list on any number of threads.  For engines that run after InteractionLoop.
	const std::vector<BridgeEvent>& events(long iter);

	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(ViscBridgeContext, Serializable,
		"What the ViscBridge functors and engines of one scene share (created by them in "
		":yref:`O.miscParams<Omega.miscParams>` on first use; nothing of it is saved): the scene's ViscBridge "
		"functors, errors found inside the interaction loop (raised by :yref:`ViscBridgeGuard` at the next step), the work "
		"of the capillary forces, the formation and rupture events of the liquid bridges, published by "
		":yref:`Law2_ScGeom_ViscBridgePhys_HertzViscous` and read by engines after the interaction loop in an order "
		"independent of the number of threads (docs/architecture.md), and the plausibility warnings already said.",
		/* attrs */,
		/* ctor */,
		/* py */
		.def("warnOnce", &ViscBridgeContext::warnCurrent, (boost::python::arg("key"), boost::python::arg("message")),
		     "Say `message` in YADE's log as a warning, once per scene and `key` (the plausibility warnings of viscbridge's "
		     "Python functions: a value no wet granulation run uses, a likely unit mistake).")
		.staticmethod("warnOnce")
	);
	// clang-format on
	DECLARE_LOGGER;
};
REGISTER_SERIALIZABLE(ViscBridgeContext);

} // namespace yade
