// Where the sun is at a time and place: the PSA algorithm of M. Blanco-Muriel, D. C. Alarcon-Padilla,
// T. Lopez-Moratalla and M. Lara-Coira, "Computing the solar vector", Solar Energy 70(5), 2001 (about 0.01
// degrees over 1999-2015), as Mitsuba's sun, sky and sunsky place it.
#pragma once

#include "scene/emitters/lat_long.h"

namespace lt {

struct SunTime {
    int year = 2010, month = 7, day = 10; // Mitsuba's defaults: Tokyo, 10 July 2010, 15:00
    double hour = 15, minute = 0, second = 0;
};

struct SunLocation {
    double latitude = 35.6894;   // degrees north
    double longitude = 139.6917; // degrees east
    double timezone = 9;         // hours ahead of UTC
};

// The sun's zenith angle and its azimuth from north toward east, in the sky frame of lat_long.h (north
// toward -z, east toward +x, up +y). Includes the parallax of the Earth's radius.
SkyAngles sunPosition(const SunTime& time, const SunLocation& location);

} // namespace lt
