// State that belongs to one scene rather than to an engine or a functor, kept in the scene's
// O.miscParams: found there, or created and added on first use.  A class attached this way is
// saved with the scene if it has attributes, and adding one never changes how older scenes load
// (they simply do not have it), which a new attribute on an existing class would
// (docs/contributing.md, "Saved scenes must keep loading").
#pragma once
#include <core/Scene.hpp>

namespace yade {

// The scene's attachment of class T, or null (none is created: e.g. while the scene is being saved).
template <class T> shared_ptr<T> existingAttachment(const Scene* scene)
{
	for (const auto& p : scene->miscParams)
		if (auto found = YADE_PTR_DYN_CAST<T>(p)) return found;
	return nullptr;
}

template <class T> shared_ptr<T> sceneAttachment(Scene* scene)
{
	if (auto found = existingAttachment<T>(scene)) return found;
	auto created = shared_ptr<T>(new T);
	scene->miscParams.push_back(created);
	return created;
}

} // namespace yade
