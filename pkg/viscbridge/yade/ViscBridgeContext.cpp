#include "viscbridge/yade/ViscBridgeContext.hpp"
#include "viscbridge/yade/SceneAttachment.hpp"
#include <core/Engine.hpp>
#include <core/InteractionLoop.hpp>
#include <core/Omega.hpp>
#include <pkg/dem/NewtonIntegrator.hpp>
#include <lib/factory/ClassFactory.hpp>
#include <algorithm>
#ifdef YADE_OPENMP
#include <omp.h>
#endif

namespace yade {

CREATE_LOGGER(ViscBridgeContext);

shared_ptr<ViscBridgeContext> ViscBridgeContext::shared(Scene* scene)
{
	return sceneAttachment<ViscBridgeContext>(scene);
}

ViscBridgeContext& ViscBridgeContext::of(Scene* scene) { return *shared(scene); }

Vector3r ViscBridgeContext::newtonGravity(const Scene* scene)
{
	const auto* newton = findEngine<NewtonIntegrator>(scene);
	return newton ? newton->gravity : Vector3r::Zero();
}

bool ViscBridgeContext::hasEngine(const Scene* scene, const std::string& className)
{
	for (const auto& e : scene->engines)
		if (e->getClassName() == className) return true;
	return false;
}

bool ViscBridgeContext::hasEngineAfterLoop(const Scene* scene, const std::string& className)
{
	bool afterLoop = false;
	for (const auto& e : scene->engines) {
		if (dynamic_cast<const InteractionLoop*>(e.get())) afterLoop = true;
		else if (dynamic_cast<const NewtonIntegrator*>(e.get())) return false;
		else if (afterLoop && !e->dead && e->getClassName() == className) return true;
	}
	return false;
}

void ViscBridgeContext::raiseAtNextStep(Scene* scene, const std::string& message)
{
	{
		std::lock_guard<std::mutex> lock(pendingMutex);
		if (pendingError.empty()) pendingError = message;
	}
	// the guard raises it; without one in the scene, one is added (by name: no engine knows another's class)
	if (hasEngine(scene, "ViscBridgeGuard")) return;
	vector<shared_ptr<Engine>> next = scene->_nextEngines.empty() ? scene->engines : scene->_nextEngines;
	next.insert(next.begin(), YADE_PTR_DYN_CAST<Engine>(ClassFactory::instance().createShared("ViscBridgeGuard")));
	scene->_nextEngines = next;
}

void ViscBridgeContext::warnOnce(const std::string& key, const std::string& message)
{
	std::lock_guard<std::mutex> lock(pendingMutex);
	if (warned.insert(key).second) LOG_WARN(message);
}

void ViscBridgeContext::warnCurrent(const std::string& key, const std::string& message)
{
	of(Omega::instance().getScene().get()).warnOnce(key, message);
}

std::string ViscBridgeContext::takePendingError()
{
	std::lock_guard<std::mutex> lock(pendingMutex);
	std::string                 msg;
	msg.swap(pendingError);
	return msg;
}

void ViscBridgeContext::beginStep(long iter, bool keepsForces)
{
	if (passOpen(iter)) return; // a second law of the same pass
	forcesKept = keepsForces;
#ifdef YADE_OPENMP
	const size_t threads = std::max(1, omp_get_max_threads());
#else
	const size_t threads = 1;
#endif
	queues.resize(threads);
	forceQueues.resize(threads);
	for (auto& q : queues)
		q.clear();
	for (auto& q : forceQueues)
		q.clear();
	publishedIter = iter;
	mergedIter = orderedIter = -1; // read before the loop of this step, or by a failed try of it: read again
	openPassIter.store(iter, std::memory_order_release);
}

void ViscBridgeContext::keepForce(const ContactForce& force) { ownQueue(forceQueues).push_back(force); }

const std::vector<const ContactForce*>& ViscBridgeContext::forces(long iter, size_t bodies)
{
	closePass();
	if (orderedIter == iter) return ordered;
	// A counting sort by the smaller id (one pass to count, one to place: cheaper than a comparison
	// sort of every contact), then each body's few contacts by the larger id.
	ordered.clear();
	firstOf.assign(bodies + 1, 0);
	size_t total = 0;
	if (publishedIter == iter)
		for (const auto& q : forceQueues)
			for (const ContactForce& f : q)
				++firstOf[f.lowerId() + 1], ++total;
	for (size_t i = 0; i < bodies; ++i)
		firstOf[i + 1] += firstOf[i];
	ordered.resize(total);
	placed.assign(firstOf.begin(), firstOf.end() - 1);
	if (publishedIter == iter)
		for (const auto& q : forceQueues)
			for (const ContactForce& f : q)
				ordered[placed[f.lowerId()]++] = &f;
	for (size_t i = 0; i < bodies; ++i)
		std::sort(ordered.begin() + firstOf[i], ordered.begin() + firstOf[i + 1],
		          [](const ContactForce* a, const ContactForce* b) { return a->higherId() < b->higherId(); });
	orderedIter = iter;
	return ordered;
}

void ViscBridgeContext::publish(const BridgeEvent& event) { ownQueue(queues).push_back(event); }

const std::vector<BridgeEvent>& ViscBridgeContext::events(long iter)
{
	closePass();
	if (mergedIter != iter) {
		merged.clear();
		if (publishedIter == iter)
			for (const auto& q : queues)
				merged.insert(merged.end(), q.begin(), q.end());
		std::sort(merged.begin(), merged.end());
		mergedIter = iter;
	}
	return merged;
}

} // namespace yade
