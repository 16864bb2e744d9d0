#include "scene/emitters/sun_position.h"

#include <cmath>

#include "math/constants.h"

namespace lt {

SkyAngles sunPosition(const SunTime& time, const SunLocation& location) {
    // Universal time in decimal hours and the days elapsed since JD 2451545.0 (noon, 1 January 2000 UT);
    // the Julian day by the integer formula of the paper (Sec. 3.1).
    const double hoursUt = time.hour - location.timezone + (time.minute + time.second / 60.0) / 60.0;
    const int a = (time.month - 14) / 12;
    const int julianDayNumber = (1461 * (time.year + 4800 + a)) / 4 + (367 * (time.month - 2 - 12 * a)) / 12 -
                                (3 * ((time.year + 4900 + a) / 100)) / 4 + time.day - 32075;
    const double n = double(julianDayNumber) - 0.5 + hoursUt / 24.0 - 2451545.0;

    // Ecliptic longitude and obliquity (radians, not reduced to [0, 2 pi)).
    const double omega = 2.1429 - 0.0010394594 * n;
    const double meanLongitude = 4.8950630 + 0.017202791698 * n;
    const double meanAnomaly = 6.2400600 + 0.0172019699 * n;
    const double eclipticLongitude = meanLongitude + 0.03341607 * std::sin(meanAnomaly) +
                                     0.00034894 * std::sin(2 * meanAnomaly) - 0.0001134 - 0.0000203 * std::sin(omega);
    const double obliquity = 0.4090928 - 6.2140e-9 * n + 0.0000396 * std::cos(omega);

    // Right ascension and declination.
    const double sinLongitude = std::sin(eclipticLongitude);
    double rightAscension = std::atan2(std::cos(obliquity) * sinLongitude, std::cos(eclipticLongitude));
    if (rightAscension < 0) rightAscension += TwoPi;
    const double declination = std::asin(std::sin(obliquity) * sinLongitude);

    // Local coordinates: hour angle from the local mean sidereal time, then zenith angle and azimuth.
    const double greenwichSiderealHours = 6.6974243242 + 0.0657098283 * n + hoursUt;
    const double localSidereal = degToRad(greenwichSiderealHours * 15 + location.longitude);
    const double latitude = degToRad(location.latitude);
    const double hourAngle = localSidereal - rightAscension;
    const double cosLatitude = std::cos(latitude), sinLatitude = std::sin(latitude);
    double zenith =
        std::acos(cosLatitude * std::cos(hourAngle) * std::cos(declination) + std::sin(declination) * sinLatitude);
    double azimuth =
        std::atan2(-std::sin(hourAngle), std::tan(declination) * cosLatitude - sinLatitude * std::cos(hourAngle));
    if (azimuth < 0) azimuth += TwoPi;
    // Parallax: the observer stands on the Earth's surface, not at its centre (mean radius over 1 AU, km).
    zenith += (6371.01 / 149597890.0) * std::sin(zenith);
    return {zenith, azimuth};
}

} // namespace lt
