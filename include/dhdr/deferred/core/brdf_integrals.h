// Integrals of the GGX lobe over the hemisphere: the split-sum DFG terms that the IBL bake
// tabulates and the multiple-scattering table is built from.
#pragma once

#include <glm/glm.hpp>
#include <vector>

namespace dhdr {

// The GGX half vectors integrateDFG draws at a roughness (Hammersley points): they do not
// depend on N·V, so a row of a table draws them once.
std::vector<glm::vec3> dfgHalfVectors(float roughness, int samples);

// The DFG terms at one (N·V, roughness) over the given half vectors: x = ∫ f/F cos (1 − v·h)⁵
// dω, y = ∫ f/F cos dω.
glm::vec2 integrateDFG(float NdotV, float roughness, const std::vector<glm::vec3>& halves);

// The DFG terms at one (N·V, roughness) by importance sampling GGX with `samples` points.
glm::vec2 integrateDFG(float NdotV, float roughness, int samples);

} // namespace dhdr
