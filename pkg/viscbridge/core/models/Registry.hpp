// THE registry of sub-models: every effect a wet contact can have, one row per model.
//
// To add a model to a slot, write its struct (see SubModel.hpp for what it holds, and a model of
// the same slot for the force kernel's signature) and add it to its slot's list below: its name is
// then accepted by Ip2_FrictMat_FrictMat_ViscBridgePhys, saved with scenes, listed by
// viscbridge.criteria, its kernels are compiled into Law2_ScGeom_ViscBridgePhys_HertzViscous, its
// step coefficient enters the time step and its capabilities decide what it may be combined with.
// (After adding one, regenerate py/viscbridge/_registry.py: `./yadew sh build/viscbridge_registry
// --python > py/viscbridge/_registry.py`; a test fails until you do.)  docs/contributing.md has
// the whole recipe, including what a new slot takes.
#pragma once
#include "viscbridge/core/models/capillary/Capillary.hpp"
#include "viscbridge/core/models/damping/ContactDamping.hpp"
#include "viscbridge/core/models/normal/NormalViscous.hpp"
#include "viscbridge/core/models/SubModel.hpp"
#include "viscbridge/core/models/tangential/TangentialViscous.hpp"
#include "viscbridge/core/util/Validation.hpp"
#include <string>
#include <string_view>

namespace viscbridge {

using NormalModels     = ModelList<NoNormalViscous, AdamsPerchard, Pitois>;
using TangentialModels = ModelList<NoTangentialViscous, WashinoTangential, SlipTangential, GoldmanTangential>;
using DampingModels    = ModelList<NoContactDamping, RestitutionContactDamping>;
using CapillaryModels  = ModelList<NoCapillary, WillettCapillary, RabinovichCapillary>;
// The first model of every slot is its 'none' (what a dry pair, or one without surface tension, gets).
static_assert(std::string_view(NormalModels::names[0]) == "none" && std::string_view(TangentialModels::names[0]) == "none"
              && std::string_view(DampingModels::names[0]) == "none" && std::string_view(CapillaryModels::names[0]) == "none");

// The slots: which Ip2 attribute selects the model (damping: none, it follows `en`) and the default.
struct NormalSlot {
	using Models                               = NormalModels;
	static constexpr const char* parameter     = "normalModel";
	static constexpr const char* defaultModel  = AdamsPerchard::name;
	static constexpr const char* description   = "normal viscous force F = -C^n v_n (physics.md P3-P6)";
};
struct TangentialSlot {
	using Models                               = TangentialModels;
	static constexpr const char* parameter     = "tangentialModel";
	static constexpr const char* defaultModel  = SlipTangential::name;
	static constexpr const char* description   = "tangential viscous force (physics.md P7-P9)";
};
struct DampingSlot {
	using Models                               = DampingModels;
	static constexpr const char* parameter     = "en";
	static constexpr const char* defaultModel  = NoContactDamping::name;
	static constexpr const char* description   = "contact damping of the dry contact, selected by en < 1 (physics.md P2b)";
};
struct CapillarySlot {
	using Models                               = CapillaryModels;
	static constexpr const char* parameter     = "capillaryModel";
	static constexpr const char* defaultModel  = NoCapillary::name;
	static constexpr const char* description   = "capillary force of the bridge (physics.md P19-P22)";
};
using Slots = std::tuple<NormalSlot, TangentialSlot, DampingSlot, CapillarySlot>;

// Index of the model called `value` in slot S; otherwise std::invalid_argument naming the parameter
// and every allowed name (a ValueError in Python).
template <class S> std::size_t modelIndex(const std::string& owner, const std::string& value)
{
	return parseName(owner, S::parameter, value, S::Models::names);
}

// The time-integration schemes of the viscous forces (Law2_…HertzViscous.integration).
enum class Integration : int { explicitEuler = 0, implicitEuler = 1 };
inline constexpr std::array<const char*, 2> integrationNames = { "explicit", "implicit" };

} // namespace viscbridge
