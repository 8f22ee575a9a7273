#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/core/util/Validation.hpp"
#include <boost/functional/hash.hpp>
#include <algorithm>
#include <atomic>
#include <limits>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <pkg/common/KinematicEngines.hpp>
#include <pkg/dem/NewtonIntegrator.hpp>
#ifdef YADE_MPI
#include <core/Subdomain.hpp>
#include <mpi.h>
#endif

namespace yade {
namespace distributed {

	static_assert(sizeof(Real) == sizeof(double), "the collectives exchange Real as MPI_DOUBLE");

#ifdef YADE_MPI
	namespace {
		// The subdomain of a scene split by yade.mpy, with its communicator; nullptr otherwise.
		const Subdomain* subdomainOf(const Scene* scene)
		{
			if (!scene->subD || scene->subD->getClassName() != "Subdomain") return nullptr;
			const auto* sd = static_cast<const Subdomain*>(scene->subD.get());
			return sd->myComm_p ? sd : nullptr;
		}
		MPI_Comm commOf(const Scene* scene) { return *subdomainOf(scene)->myComm_p; }
		// mpy's per-step state exchange (a PyRunner it inserts after NewtonIntegrator when it splits
		// the scene and kills when it merges it): the one sign, visible from C++, that every rank is
		// stepping its part of the scene right now.
		bool exchangeRuns(const Scene* scene)
		{
			for (const auto& e : scene->engines)
				if (e && e->label == "sendRecvStatesRunner" && !e->dead) return true;
			return false;
		}
	}
#endif

	bool active(const Scene* scene)
	{
#ifdef YADE_MPI
		int initialised = 0, finalised = 0;
		MPI_Initialized(&initialised);
		MPI_Finalized(&finalised);
		if (!initialised || finalised || !subdomainOf(scene)) return false;
		int size = 1;
		MPI_Comm_size(commOf(scene), &size);
		return size > 1 && exchangeRuns(scene);
#else
		return false;
#endif
	}

	namespace {
		// activeThisStep(): the answer for (scene, its subdomain object, step), computed by the first
		// thread that asks in a step.  The key is invalidated before it is rewritten, so a reader
		// either sees a complete entry for its own step or recomputes under the lock.
		std::atomic<const Scene*> cachedScene { nullptr };
		std::atomic<const void*>  cachedSubdomain { nullptr };
		std::atomic<long>         cachedIter { -1 };
		std::atomic<bool>         cachedActive { false };
		std::mutex                cacheMutex;
		bool cacheHit(const Scene* scene)
		{
			return cachedIter.load(std::memory_order_acquire) == scene->iter && cachedScene.load(std::memory_order_acquire) == scene
			        && cachedSubdomain.load(std::memory_order_acquire) == static_cast<const void*>(scene->subD.get());
		}
	}

	bool activeThisStep(const Scene* scene)
	{
#ifdef YADE_MPI
		if (cacheHit(scene)) return cachedActive.load(std::memory_order_acquire);
		std::lock_guard<std::mutex> lock(cacheMutex);
		if (!cacheHit(scene)) {
			cachedIter.store(-1, std::memory_order_release);
			cachedActive.store(active(scene), std::memory_order_release);
			cachedScene.store(scene, std::memory_order_release);
			cachedSubdomain.store(scene->subD.get(), std::memory_order_release);
			cachedIter.store(scene->iter, std::memory_order_release);
		}
		return cachedActive.load(std::memory_order_acquire);
#else
		return false;
#endif
	}

	int rank(const Scene* scene)
	{
#ifdef YADE_MPI
		if (!active(scene)) return 0;
		int r = 0;
		MPI_Comm_rank(commOf(scene), &r);
		return r;
#else
		return 0;
#endif
	}

	int ranks(const Scene* scene)
	{
#ifdef YADE_MPI
		if (!active(scene)) return 1;
		int n = 1;
		MPI_Comm_size(commOf(scene), &n);
		return n;
#else
		return 1;
#endif
	}

	bool isSubdomainBody(const Body& b)
	{
#ifdef YADE_MPI
		return b.getIsSubdomain();
#else
		return false;
#endif
	}

	bool Ownership::interaction(const Interaction& I, const Scene* scene) const { return pair(I.getId1(), I.getId2(), scene); }

	bool Ownership::pair(Body::id_t id1, Body::id_t id2, const Scene* scene) const
	{
#ifdef YADE_MPI
		if (!split) return true;
		const BodyContainer& bodies = *scene->bodies;
		if (!bodies.exists(id1) || !bodies.exists(id2)) return false;
		return std::max(bodies[id1]->subdomain, bodies[id2]->subdomain) == rank;
#else
		return true;
#endif
	}

	Ownership ownership(const Scene* scene)
	{
		Ownership o;
		o.split = active(scene);
		o.rank  = o.split ? rank(scene) : 0;
		return o;
	}

	Ownership ownershipThisStep(const Scene* scene)
	{
		Ownership o;
		o.split = activeThisStep(scene);
#ifdef YADE_MPI
		o.rank = o.split ? scene->subdomain : 0; // mpy sets Scene::subdomain to the rank
#endif
		return o;
	}

	size_t ownedBodiesSignature(const Scene* scene)
	{
#ifdef YADE_MPI
		if (!active(scene)) return 0;
		// from the bodies' own subdomain: mpy's list (Subdomain::ids) is not updated by migrateBodies
		const int me = rank(scene);
		size_t    h  = 1;
		for (const auto& b : *scene->bodies)
			if (b && b->subdomain == me) boost::hash_combine(h, b->id);
		return h;
#else
		return 0;
#endif
	}

	std::vector<double> allGather(const Scene* scene, const std::vector<double>& mine)
	{
#ifdef YADE_MPI
		if (!active(scene)) return mine;
		const MPI_Comm comm = commOf(scene);
		int            n    = 1;
		MPI_Comm_size(comm, &n);
		std::vector<double> all(mine.size() * static_cast<size_t>(n));
		MPI_Allgather(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, all.data(), static_cast<int>(mine.size()), MPI_DOUBLE, comm);
		return all;
#else
		return mine;
#endif
	}

	std::vector<double> allGatherJoined(const Scene* scene, const std::vector<double>& mine)
	{
#ifdef YADE_MPI
		if (!active(scene)) return mine;
		const MPI_Comm comm = commOf(scene);
		int            n    = 1, count = static_cast<int>(mine.size());
		MPI_Comm_size(comm, &n);
		std::vector<int> counts(static_cast<size_t>(n)), offsets(static_cast<size_t>(n), 0);
		MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
		for (size_t r = 1; r < counts.size(); ++r)
			offsets[r] = offsets[r - 1] + counts[r - 1];
		std::vector<double> all(static_cast<size_t>(offsets.back() + counts.back()));
		MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, comm);
		return all;
#else
		return mine;
#endif
	}

	void sum(const Scene* scene, std::vector<Real*> values)
	{
		if (!active(scene)) return;
		std::vector<double> mine;
		for (const Real* v : values)
			mine.push_back(*v);
		const std::vector<double> all = allGather(scene, mine);
		const size_t              k   = values.size();
		for (size_t j = 0; j < k; ++j) {
			Real s = 0;
			for (size_t r = 0; r < all.size() / k; ++r)
				s += all[r * k + j];
			*values[j] = s;
		}
	}

	Real sum(const Scene* scene, Real value)
	{
		sum(scene, std::vector<Real*> { &value });
		return value;
	}

	bool any(const Scene* scene, bool mine) { return sum(scene, mine ? 1.0 : 0.0) > 0; }
	bool all(const Scene* scene, bool mine) { return !any(scene, !mine); }

	ArgMin argMin(const Scene* scene, Real value, long id)
	{
		if (!active(scene)) return { value, id, 0 };
		const std::vector<double> all = allGather(scene, { value, static_cast<double>(id) });
		ArgMin                    best { all[0], static_cast<long>(all[1]), 0 };
		for (size_t r = 1; r < all.size() / 2; ++r)
			if (all[2 * r] < best.value || (std::isnan(best.value) && !std::isnan(all[2 * r])))
				best = { all[2 * r], static_cast<long>(all[2 * r + 1]), static_cast<int>(r) };
		return best;
	}

	std::string broadcast(const Scene* scene, int root, const std::string& text)
	{
#ifdef YADE_MPI
		if (!active(scene)) return text;
		const MPI_Comm comm = commOf(scene);
		long           size = static_cast<long>(text.size());
		MPI_Bcast(&size, 1, MPI_LONG, root, comm);
		std::string out = text;
		out.resize(static_cast<size_t>(size));
		if (size > 0) MPI_Bcast(&out[0], static_cast<int>(size), MPI_CHAR, root, comm);
		return out;
#else
		return text;
#endif
	}

	std::string rankLabel(const Scene* scene, int r)
	{
		if (!active(scene)) return "";
		return "(yade.mpy rank " + std::to_string(r) + " of " + std::to_string(ranks(scene)) + ") ";
	}

	namespace {
		// (has an error, is it an invalid_argument) of every rank, and the message of the first one.
		struct FirstError {
			std::string message;
			bool        invalidArgument = false;
		};
		FirstError firstOf(const Scene* scene, const std::string& mine, bool mineInvalid)
		{
			const std::vector<double> flags = allGather(scene, { mine.empty() ? 0.0 : 1.0, mineInvalid ? 1.0 : 0.0 });
			for (size_t r = 0; r < flags.size() / 2; ++r)
				if (flags[2 * r] > 0) {
					const int root = static_cast<int>(r);
					return { rankLabel(scene, root) + broadcast(scene, root, mine), flags[2 * r + 1] > 0 };
				}
			return {};
		}
	}

	std::string firstError(const Scene* scene, const std::string& mine)
	{
		if (!active(scene)) return mine;
		return firstOf(scene, mine, false).message;
	}

	void collectively(const Scene* scene, const std::function<void()>& work)
	{
		if (!active(scene)) {
			work();
			return;
		}
		std::string error;
		bool        failed = false, invalid = false;
		try {
			work();
		} catch (const std::invalid_argument& e) {
			error   = e.what();
			failed  = true;
			invalid = true;
		} catch (const std::exception& e) {
			error  = e.what();
			failed = true;
		}
		if (failed && error.empty()) error = "(an exception without a message)";
		const FirstError first = firstOf(scene, error, invalid);
		if (first.message.empty()) return;
		if (first.invalidArgument) throw std::invalid_argument(first.message);
		throw std::runtime_error(first.message);
	}

	namespace {
		Real minKeepingNaN(Real a, Real b) { return (std::isnan(a) || std::isnan(b)) ? std::numeric_limits<Real>::quiet_NaN() : std::min(a, b); }
	}

	void requireSameDt(const Scene* scene, const std::vector<double>& dts, const std::string& who)
	{
		if (std::all_of(dts.begin(), dts.end(), [&](double dt) { return dt == dts[0]; })) return;
		std::ostringstream msg;
		msg << who << ": O.dt differs between the ranks of yade.mpy at step " << scene->iter << ":";
		for (size_t r = 0; r < dts.size(); ++r)
			msg << (r ? "," : "") << " rank " << r << ": dt = " << viscbridge::formatValue(dts[r]) << " s";
		msg << ". Every rank must step with the same dt: set O.dt to the same value on every rank (before mp.mpirun), or let "
		       "ViscBridgeTimeStepper choose it (it takes the minimum over the ranks).";
		throw std::runtime_error(msg.str());
	}

	void requireSameDt(const Scene* scene, const std::string& who)
	{
		if (!active(scene)) return;
		requireSameDt(scene, allGather(scene, { scene->dt }), who);
	}

	void reduceTimeStepBound(const Scene* scene, Real& collision, Real& viscous, Real& combined, Body::id_t& criticalBody)
	{
		if (!active(scene)) return;
		const std::vector<double> all = allGather(scene, { collision, viscous, combined, static_cast<double>(criticalBody), scene->dt });
		const size_t              k   = 5, n = all.size() / k;
		std::vector<double>       dts(n);
		// from rank 0 upwards, so that every rank picks the same critical body (ties: the lowest rank)
		collision = viscous = combined = std::numeric_limits<Real>::infinity();
		criticalBody                   = -1;
		for (size_t r = 0; r < n; ++r) {
			const double* v = &all[r * k];
			dts[r]          = v[4];
			collision       = minKeepingNaN(collision, v[0]);
			viscous         = minKeepingNaN(viscous, v[1]);
			// a NaN bound (a broken body) wins, so that it is reported as in a serial run
			if (std::isnan(combined)) continue;
			if (std::isnan(v[2]) || v[2] < combined || (criticalBody < 0 && v[3] >= 0 && v[2] == combined)) {
				combined     = v[2];
				criticalBody = static_cast<Body::id_t>(v[3]);
			}
		}
		requireSameDt(scene, dts, "ViscBridgeTimeStepper");
	}

	void requireParticlesOnWorkers(const Scene* scene)
	{
#ifdef YADE_MPI
		if (!active(scene) || rank(scene) != 0) return;
		long       moving = 0;
		Body::id_t first  = -1;
		for (const auto& b : *scene->bodies)
			if (b && b->subdomain == 0 && !b->getIsSubdomain() && b->isDynamic() && b->state->mass > 0) {
				if (first < 0) first = b->getId();
				++moving;
			}
		if (moving == 0) return;
		throw std::invalid_argument("Body #" + std::to_string(first) + " (and " + std::to_string(moving - 1)
		                            + " more) is a moving body of subdomain 0, yade.mpy's master, which only holds boundaries: mpy does not send "
		                              "the master's bodies to the workers, so they would be frozen for their neighbours there (or the run is "
		                              "serial). Assign every free particle to a worker (Body.subdomain >= 1) before mp.mpirun, e.g. with "
		                              "viscbridge.mpi.decompose() or mp.DOMAIN_DECOMPOSITION = True.");
#endif
	}

	void refuseClumps(const Scene* scene)
	{
		if (!active(scene)) return;
		for (const auto& b : *scene->bodies)
			if (b && b->isClump())
				throw std::invalid_argument("Body #" + std::to_string(b->getId())
				                            + " is a clump, and yade.mpy distributes bodies one by one: it has no notion of a clump (a clump has "
				                              "no bound, so it never enters a subdomain's intersections), and its members' copies on a neighbouring "
				                              "rank would not follow it. Run scenes with clumps in one process (OpenMP threads, -j), both schemes "
				                              "take clumps there.");
	}

	bool isMasterBoundary(const Body& b)
	{
#ifdef YADE_MPI
		return b.subdomain == 0 && !b.isDynamic() && !b.getIsSubdomain() && !b.isClumpMember();
#else
		return false;
#endif
	}

	namespace {
		bool boundariesMoveOnWorkers(const Scene* scene)
		{
			bool afterNewton = false;
			for (const auto& e : scene->engines) {
				if (dynamic_cast<const NewtonIntegrator*>(e.get())) afterNewton = true;
				else if (afterNewton && !e->dead && e->getClassName() == "ViscBridgeBoundaryMotion")
					return true;
			}
			return false;
		}
	}

	void refuseMovingBoundaries(const Scene* scene)
	{
		if (!active(scene)) return;
		const bool moved = boundariesMoveOnWorkers(scene);
		if (moved && !scene->isPeriodic) return;
		const std::string why = moved
		        ? " in a periodic cell split by yade.mpy: ViscBridgeBoundaryMotion moves the master's boundaries on the workers as "
		          "NewtonIntegrator does in a non-periodic scene only. Run it in one process with OpenMP threads (yade -j N)."
		        : " in a scene split by yade.mpy, and O.engines has no ViscBridgeBoundaryMotion after NewtonIntegrator: mpy moves the "
		          "master's bodies on the master only, and the workers' copies would stay where they were, so the particles there "
		          "would meet a wall that is not where it is. viscbridge.mpi.decompose() adds the engine; or append "
		          "ViscBridgeBoundaryMotion() after NewtonIntegrator yourself.";
		auto refuse = [&](Body::id_t id, const std::string& how) {
			throw std::invalid_argument("Body #" + std::to_string(id) + " is a boundary that moves (" + how + ")" + why);
		};
		for (const auto& e : scene->engines) {
			const PartialEngine* driving = dynamic_cast<const KinematicEngine*>(e.get());
			if (!driving) driving = dynamic_cast<const CombinedKinematicEngine*>(e.get());
			if (!driving || driving->dead) continue;
			for (Body::id_t id : driving->ids)
				if (const auto& b = Body::byId(id, const_cast<Scene*>(scene)); b && !b->isDynamic() && !b->getIsSubdomain())
					refuse(id, "driven by a " + e->getClassName());
		}
		for (const auto& b : *scene->bodies)
			if (b && !b->isDynamic() && !b->getIsSubdomain() && (!b->state->vel.isZero(0) || !b->state->angVel.isZero(0)))
				refuse(b->getId(), "its velocity is set");
	}

	void requireOneSubdomainWhenSerial(const Scene* scene)
	{
#ifdef YADE_MPI
		if (active(scene)) return;
		for (const auto& b : *scene->bodies)
			if (b && b->subdomain != scene->subdomain && !b->getIsSubdomain() && b->isDynamic() && b->state->mass > 0)
				throw std::invalid_argument("Body #" + std::to_string(b->getId()) + ".subdomain=" + std::to_string(b->subdomain)
				                            + " but the scene runs in one process (as subdomain " + std::to_string(scene->subdomain)
				                            + "): NewtonIntegrator would never move it. A scene merged by yade.mpy (mp.mpirun(..., withMerge=True), "
				                              "or saved after it) runs on serially after viscbridge.mpi.to_serial(); on one rank, mp.mpirun() is "
				                              "a plain O.run(), so leave Body.subdomain at 0 there.");
#endif
	}

	Halo halo(const Scene* scene)
	{
		Halo h;
#ifdef YADE_MPI
		if (!active(scene)) return h;
		const Subdomain& sd = *subdomainOf(scene);
		const int        me = rank(scene);
		if (me == 0 || sd.intersections.size() <= static_cast<size_t>(me)) return h;
		for (const Body::id_t other : sd.intersections[me]) {
			if (other == 0 || other == me || static_cast<size_t>(other) >= sd.intersections.size()) continue;
			h.ranks.push_back(other);
			h.sent.push_back(sd.intersections[other]);
			h.received.push_back(static_cast<size_t>(other) < sd.mirrorIntersections.size() ? sd.mirrorIntersections[other] : std::vector<Body::id_t>());
		}
#endif
		return h;
	}

	void exchange(const Scene* scene, const Halo& h, const std::vector<std::vector<double>>& send, std::vector<std::vector<double>>& received)
	{
#ifdef YADE_MPI
		if (h.ranks.empty()) return;
		const MPI_Comm           comm = commOf(scene);
		const int                tag  = 31517; // none of mpy's
		std::vector<MPI_Request> requests(2 * h.ranks.size());
		for (size_t j = 0; j < h.ranks.size(); ++j)
			MPI_Irecv(received[j].data(), static_cast<int>(received[j].size()), MPI_DOUBLE, h.ranks[j], tag, comm, &requests[2 * j]);
		for (size_t j = 0; j < h.ranks.size(); ++j)
			MPI_Isend(send[j].data(), static_cast<int>(send[j].size()), MPI_DOUBLE, h.ranks[j], tag, comm, &requests[2 * j + 1]);
		std::vector<MPI_Status> status(requests.size());
		if (MPI_Waitall(static_cast<int>(requests.size()), requests.data(), status.data()) != MPI_SUCCESS)
			throw std::runtime_error("ViscBridge: the halo exchange between the ranks of yade.mpy failed (mismatched subdomain lists?).");
#endif
	}

} // namespace distributed
} // namespace yade
