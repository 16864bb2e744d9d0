// The Hosek-Wilkie RGB dataset (hosek_wilkie_data.cpp, the authors' coefficients and their license).
//
// Layout of each channel, outermost first: ground albedo 0 and 1, turbidity 1 to 10, the six control
// points of a quintic Bezier curve over (solar elevation / (pi/2))^(1/3), and (configuration only) the
// nine parameters of the model in the order A B C D E F G I H (Hosek and Wilkie 2012, Eq. 9; the dataset
// stores I before H).
#pragma once

namespace lt::hosek_wilkie {

inline constexpr int ConfigurationSize = 2 * 10 * 6 * 9;
inline constexpr int RadianceSize = 2 * 10 * 6;

extern const double RgbConfiguration[3][ConfigurationSize];
extern const double RgbRadiance[3][RadianceSize];

} // namespace lt::hosek_wilkie
