// Distributed: a scene that is one subdomain of a yade.mpy run, and the few collective operations
// ViscBridge's global engines (time stepper, guard, implicit solver) need across its ranks.
//
// Under yade.mpy every rank holds its own bodies (Body::subdomain == its rank), copies ("mirrors")
// of the neighbours' bodies near its boundary, and every interaction that touches one of its own
// bodies; rank 0 (the master) holds the bodies assigned to subdomain 0 (usually walls) and no
// particles, and runs the same engines at the same steps as the workers.  A quantity of the whole
// scene is then a reduction over the ranks, computed here the same way on every rank, so that the
// ranks take the same decisions (same dt, same energy check, same stop) at the same step.
//
// Every function is a plain local no-op when the scene is not distributed (no MPI, MPI not
// initialised, a serial run, or after mpy.mergeScene()): serial runs are not changed in any way.
// The collectives must be called by all ranks at the same point of the same step.
#pragma once
#include <core/Body.hpp>
#include <core/Interaction.hpp>
#include <core/Scene.hpp>
#include <functional>
#include <string>
#include <vector>

namespace yade {
namespace distributed {

	// Whether the scene runs split by yade.mpy right now: MPI is initialised, the scene's subdomain
	// has a communicator of more than one rank, and mpy's state exchange is active (mpy inserts it
	// with splitScene() and switches it off with mergeScene()).  Same answer on every rank.
	bool active(const Scene* scene);
	// The same, cached per step: for the interaction loop (called by many threads, every interaction).
	bool activeThisStep(const Scene* scene);
	int  rank(const Scene* scene); // 0 when not distributed
	int  ranks(const Scene* scene); // 1 when not distributed

	// mpy's own Subdomain bodies (a body per worker, mass 0): not part of the physics.
	bool isSubdomainBody(const Body& b);

	// Which bodies and interactions a rank accounts for, so that sums over ranks count each once:
	// a body on the rank that owns it; an interaction (present on the ranks of both its bodies) on
	// the higher of the two (a wall of the master meets a worker's particle only on the worker).
	struct Ownership {
		bool split = false;
		int  rank  = 0;
		bool body(const Body& b) const
		{
#ifdef YADE_MPI
			return !split || b.subdomain == rank;
#else
			return true;
#endif
		}
		bool interaction(const Interaction& I, const Scene* scene) const;
		// The same for the pair of bodies id1, id2 (false when this rank holds either of them not).
		bool pair(Body::id_t id1, Body::id_t id2, const Scene* scene) const;
	};
	Ownership ownership(const Scene* scene);        // uses active()
	Ownership ownershipThisStep(const Scene* scene); // uses activeThisStep()
	// Changes when the set of bodies this rank owns changes (mpy reallocation); 0 when not distributed.
	size_t ownedBodiesSignature(const Scene* scene);

	// Values of every rank, rank after rank (every rank gets the same vector).
	std::vector<double> allGather(const Scene* scene, const std::vector<double>& mine);
	// The same with a length of its own on every rank: all ranks' values joined in rank order.
	std::vector<double> allGatherJoined(const Scene* scene, const std::vector<double>& mine);
	// In place: the sum over ranks (in rank order, so bit-identical on every rank).
	void sum(const Scene* scene, std::vector<Real*> values);
	Real sum(const Scene* scene, Real value);
	bool any(const Scene* scene, bool mine);
	bool all(const Scene* scene, bool mine);
	// The smallest value over ranks, the id that goes with it and the rank it comes from (ties: the
	// lowest rank); the local pair and rank 0 when not distributed.
	struct ArgMin {
		Real value;
		long id;
		int  rank;
	};
	ArgMin argMin(const Scene* scene, Real value, long id);
	// `text` of rank `root`, on every rank.
	std::string broadcast(const Scene* scene, int root, const std::string& text);
	// "(yade.mpy rank r of n) " when distributed, "" otherwise: for messages naming the rank.
	std::string rankLabel(const Scene* scene, int rank);

	// The error of the lowest rank that has one (prefixed with its rank), on every rank; "" if none.
	std::string firstError(const Scene* scene, const std::string& mine);
	// Runs `work`; when it throws on any rank, every rank throws the first rank's error (as a
	// std::invalid_argument if that one was, else std::runtime_error), so that no rank is left
	// waiting in the next collective.  Serially: just runs `work`.
	void collectively(const Scene* scene, const std::function<void()>& work);
	// Throws std::runtime_error on every rank when O.dt is not the same on all of them, naming the
	// ranks and their dt (a rank stepping with another dt would silently desynchronise the scene).
	void requireSameDt(const Scene* scene, const std::string& who);
	// The same check on the dt of every rank, already gathered (local: no communication).
	void requireSameDt(const Scene* scene, const std::vector<double>& dts, const std::string& who);
	// The time stepper's bounds [s] (each the minimum over the ranks) and the body with the smallest
	// combined bound, in one exchange that also checks, like requireSameDt, that O.dt is the same.
	void reduceTimeStepBound(const Scene* scene, Real& collision, Real& viscous, Real& combined, Body::id_t& criticalBody);

	// On the master (rank 0): std::invalid_argument if it owns a moving particle.  mpy never sends
	// the master's states to the workers (unless mpy.MASTER_UPDATE_STATES), so its particles would
	// be frozen for their neighbours on the workers, or, if all stay there, the run is serial.
	void requireParticlesOnWorkers(const Scene* scene);

	// Split by yade.mpy: std::invalid_argument if the scene has a clump.  mpy assigns, sends and
	// mirrors bodies one by one and has no notion of a clump (a clump has no bound, so it is never in
	// a subdomain's intersections): its members' copies on a neighbour would not follow it.
	void refuseClumps(const Scene* scene);

	// Split by yade.mpy: std::invalid_argument if a boundary (a body that is not dynamic) moves — a
	// kinematic engine drives it or its velocity is set — and no ViscBridgeBoundaryMotion after
	// NewtonIntegrator moves it on the workers (mpy moves the master's bodies on the master only: the
	// workers' copies would stand still for their particles), or the cell is periodic.
	void refuseMovingBoundaries(const Scene* scene);
	// A body of the master that NewtonIntegrator moves without forces there (not dynamic; not mpy's
	// Subdomain body): what ViscBridgeBoundaryMotion moves on the workers.
	bool isMasterBoundary(const Body& b);

	// When the scene is not split (serial, or merged by mpy.mergeScene()): std::invalid_argument if a
	// moving body belongs to another subdomain than the scene's, since NewtonIntegrator (built with
	// MPI) never moves such a body: a merged scene continued serially would silently freeze.
	void requireOneSubdomainWhenSerial(const Scene* scene);

	// This rank's halo under yade.mpy, from mpy's own lists (Subdomain::intersections and
	// mirrorIntersections): for every neighbouring worker, the ids of this rank's bodies that it
	// mirrors (`sent`) and the ids of its bodies mirrored here (`received`), in the same order on both
	// sides.  The master (rank 0) has no halo: it owns no particles and receives no states.
	struct Halo {
		std::vector<int>                     ranks;
		std::vector<std::vector<Body::id_t>> sent, received;
	};
	Halo halo(const Scene* scene);
	// Point-to-point exchange with the halo's neighbours: sends send[j] to ranks[j] and receives into
	// received[j], which the caller sizes (a message of another size is an error).
	void exchange(const Scene* scene, const Halo& halo, const std::vector<std::vector<double>>& send, std::vector<std::vector<double>>& received);

} // namespace distributed
} // namespace yade
