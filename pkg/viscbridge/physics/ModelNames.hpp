// The selectable sub-models by name (the strings users set on the Ip2 and Law2 functors).
#pragma once
#include <array>
#include <stdexcept>
#include <string>

namespace viscbridge {

enum class NormalModel : int { none = 0, adamsPerchard = 1, pitois = 2 };
enum class TangentialModel : int { none = 0, washino = 1, slip = 2, goldman = 3 };
enum class Integration : int { explicitEuler = 0, implicitEuler = 1 };

inline constexpr std::array<const char*, 3> normalModelNames     = { "none", "adamsPerchard", "pitois" };
inline constexpr std::array<const char*, 4> tangentialModelNames = { "none", "washino", "slip", "goldman" };
inline constexpr std::array<const char*, 2> integrationNames     = { "explicit", "implicit" };

// Index of `value` in `names`; otherwise std::invalid_argument naming the parameter and the
// allowed values (YADE turns it into a Python ValueError).
template <std::size_t N> int parseName(const std::string& owner, const std::string& parameter, const std::string& value, const std::array<const char*, N>& names)
{
	std::string allowed;
	for (std::size_t i = 0; i < N; ++i) {
		if (value == names[i]) return static_cast<int>(i);
		allowed += std::string(i ? ", '" : "'") + names[i] + "'";
	}
	throw std::invalid_argument(owner + "." + parameter + "='" + value + "' is not a known model; allowed: " + allowed + ".");
}

} // namespace viscbridge
