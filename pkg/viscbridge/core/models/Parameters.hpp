// The numeric parameters of Ip2_FrictMat_FrictMat_ViscBridgePhys: name, unit, default and allowed
// range, in one table that the Ip2 validates against, its attribute defaults come from and the
// Python tools read (py/viscbridge/_registry.py is generated from it).
#pragma once
#include "viscbridge/core/util/Validation.hpp"
#include "viscbridge/core/linalg/Types.hpp"
#include <array>
#include <limits>
#include <string>

namespace viscbridge {

struct ParameterSpec {
	const char* name;
	const char* unit;         // "" for a dimensionless one
	double      defaultValue;
	double      lo, hi;       // hi = inf: no upper bound
	bool        loOpen, hiOpen;
	const char* zeroMeans;    // what the value 0 stands for, or "" ("0 means ..." in the message)

	// std::invalid_argument naming `owner.name`, the value and the range, unless v is allowed.
	void check(const std::string& owner, double v) const
	{
		const std::string unitText = *unit ? std::string(" [") + unit + "]" : std::string();
		const std::string zeroText = *zeroMeans ? std::string("; 0 means ") + zeroMeans : std::string();
		if (hi == std::numeric_limits<double>::infinity() && lo == 0 && !loOpen) requireNonNegative(owner, name, v, unitText + zeroText);
		else requireInRange(owner, name, v, lo, loOpen, hi, hiOpen);
	}
};

namespace parameters {
	inline constexpr double          inf = std::numeric_limits<double>::infinity();
	inline constexpr ParameterSpec   viscosity { "viscosity", "Pa·s", 0, 0, inf, false, true, "dry" };
	inline constexpr ParameterSpec   bridgeVolume { "bridgeVolume", "m³", 0, 0, inf, false, true, "bridgeVolumeRel times the particle volume" };
	inline constexpr ParameterSpec   bridgeVolumeRel { "bridgeVolumeRel", "", 0.01, 0, 1, true, false, "" };
	inline constexpr ParameterSpec   contactAngle { "contactAngle", "rad", 0, 0, pi / 2, false, false, "" };
	inline constexpr ParameterSpec   sMin { "sMin", "m", 0, 0, inf, false, true, "sMinRel times the reduced radius" };
	inline constexpr ParameterSpec   sMinRel { "sMinRel", "", 1e-3, 0, 1, true, false, "" };
	inline constexpr ParameterSpec   formationDistance { "formationDistance", "m", 0, 0, inf, false, true, "at contact" };
	inline constexpr ParameterSpec   en { "en", "", 1, 0, 1, true, false, "" };
	inline constexpr ParameterSpec   surfaceTension { "surfaceTension", "N/m", 0, 0, inf, false, true, "no capillary force" };
	inline constexpr std::array<ParameterSpec, 9> all { viscosity, bridgeVolume, bridgeVolumeRel, contactAngle, sMin, sMinRel, formationDistance, en, surfaceTension };
}

} // namespace viscbridge
