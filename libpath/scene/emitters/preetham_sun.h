// The radiance of the sun's disk seen through the atmosphere: A. J. Preetham, P. Shirley and B. Smits,
// "A Practical Analytic Model for Daylight", SIGGRAPH 1999, Appendix A.2: the extraterrestrial solar
// spectrum attenuated by Rayleigh scattering, aerosols (turbidity), ozone, mixed gases and water vapour
// along the relative optical mass of the sun's zenith angle (the absorption tables are Iqbal's, "An
// Introduction to Solar Radiation", 1983, pp. 115-132, as the paper gives them).
#pragma once

#include "math/spectrum.h"

namespace lt {

// Radiance of the sun disk, linear sRGB, for a sun at `zenith` radians (below 93.885 degrees, where the
// optical mass formula holds) and turbidity in [1, 10]. Converted as Mitsuba 0.5/0.6 converts it in RGB
// mode (spectrumToXyz, no white balance), so that sun-lit scenes keep their brightness and colour.
Spectrum preethamSunRadiance(double zenith, double turbidity);

} // namespace lt
