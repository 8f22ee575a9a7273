// What every sub-model of a wet contact is made of.  A sub-model is one struct (see
// NormalViscous.hpp, TangentialViscous.hpp, ContactDamping.hpp, Capillary.hpp) with
//   - `name`          the string users select it by (and the name saved with a scene);
//   - `capabilities`  what it is (Capabilities below): the checks that combine models read these
//                     flags, never a model's name;
//   - `energyKeys`    the O.energy keys it books (EnergyKeys.hpp): the law books its energy under these;
//   - `Constants`     the numbers it needs per interaction, built once by `make(BridgeInputs)` when
//                     the interaction's physics is created (and again after a scene is loaded);
//   - its force kernel (the slot fixes the signature) and, for the time step, `stepCoefficient`
//     (damping at its stiffest, N·s/m) and/or `stepStiffness` (N/m).
// Models are registered in SubModels.hpp, one row each; everything else derives from that list.
#pragma once
#include "viscbridge/core/models/EnergyKeys.hpp"
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstring>
#include <new>
#include <tuple>
#include <type_traits>

namespace viscbridge {

struct Capabilities {
	bool enabled;         // computes anything at all ('none' does not: its kernel is compiled away)
	bool dissipative;     // its power is never positive (the implicit solver needs a symmetric PSD damping)
	bool conservative;    // a force of position only, with a potential (booked as work, counted by the guard)
	bool beyondContact;   // acts at a gap, so the interaction lives as long as the bridge
	bool implicitCapable; // ViscBridgeImplicitSolver can integrate it (its damping is symmetric)
};

// Everything a sub-model's constants can be built from (per interaction, physics.md §1).
struct BridgeInputs {
	double viscosity = 0;      // μ [Pa·s]
	double rBar = 0;           // reduced radius r̄ [m]
	double radius1 = 0;        // true radii, 0 for a wall, facet or box side [m]
	double radius2 = 0;
	double mEff = 0;           // reduced mass m* [kg]
	double volume = 0;         // bridge volume V [m³]
	double sMin = 0;           // minimum gap S_min (P6) [m]
	double sRup = 0;           // rupture distance (P11) [m]
	double contactAngle = 0;   // θ [rad]
	double surfaceTension = 0; // γ [N/m]
	double dampingRatio = 0;   // β of the dry contact's dashpots (P2b), from its restitution e_n
};

// Room for one model's constants in a fixed-size block: the block of an interaction holds one
// model per slot, whichever was selected, without the block's type depending on the selection.
template <std::size_t Bytes> class alignas(double) ConstantsStorage {
public:
	template <class C> void store(const C& c)
	{
		static_assert(sizeof(C) <= Bytes && std::is_trivially_copyable_v<C>, "a model's Constants must fit and be trivially copyable");
		new (bytes) C(c);
	}
	template <class C> const C& as() const { return *std::launder(reinterpret_cast<const C*>(bytes)); }

private:
	unsigned char bytes[Bytes] {};
};

// The models of one slot, in the order of their registration (the index is only used at run time,
// never saved: scenes store names).
template <class... M> struct ModelList {
	static constexpr std::size_t size = sizeof...(M);
	using Tuple                       = std::tuple<M...>;
	template <std::size_t I> using At = std::tuple_element_t<I, Tuple>;
	static constexpr std::array<const char*, size> names { M::name... };
	static constexpr std::array<Capabilities, size> capabilities { M::capabilities... };
	static constexpr std::size_t largest = std::max({ sizeof(M)... }); // the room a model of the slot needs
};

// Calls f(std::integral_constant<size_t, I>) for the model index I chosen at run time: how a slot's
// constants are built and its step coefficient found without a switch written per model.
template <std::size_t I = 0, class List, class F> void visitModel(std::size_t index, const List& list, F&& f)
{
	if constexpr (I < List::size) {
		if (index == I) f(std::integral_constant<std::size_t, I>());
		else visitModel<I + 1>(index, list, f);
	}
}

} // namespace viscbridge
