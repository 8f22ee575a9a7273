// The contact network of a live scene as the time step's operator sees it (physics.md P16–P18):
// one NetworkPair per interaction that damps or stiffens, from the same constants the law uses.
#pragma once
#include "viscbridge/core/timestep/NetworkSpectrum.hpp"
#include "viscbridge/yade/ContactForce.hpp"
#include <core/Scene.hpp>
#include <vector>

namespace yade {

struct NetworkOfScene {
	viscbridge::NetworkOperator op;
	std::vector<int>            compactOf; // body id → index in op (−1: no degrees of freedom)
	std::vector<Body::id_t>     idOf;      // index in op → body id
	OrderedContacts             contacts;  // gather()'s scratch
	// Rebuilds op from the scene's interactions; viscousExplicit: whether bridges damp explicitly.
	void gather(Scene* scene, bool viscousExplicit);
	// The mode as a vector of op from per-body-id storage, and back.
	void modeFromIds(const std::vector<viscbridge::Vec6>& byId, viscbridge::VecX& mode) const;
	void modeToIds(const viscbridge::VecX& mode, std::vector<viscbridge::Vec6>& byId) const;
};

} // namespace yade
