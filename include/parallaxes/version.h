// ParallaxES's version, as the package (ParallaxESConfigVersion.cmake,
// parallaxes.pc) gives it. CHANGELOG.md says what each version changed and
// what a host must change. Kept here by hand, beside the project(VERSION)
// in CMakeLists.txt: configuring checks that the two agree.
#pragma once

#define PARALLAXES_VERSION_MAJOR 0
#define PARALLAXES_VERSION_MINOR 3
#define PARALLAXES_VERSION_PATCH 0
#define PARALLAXES_VERSION_STRING "0.3.0"
// One number to compare: PARALLAXES_VERSION >= PARALLAXES_MAKE_VERSION(0, 2, 0).
#define PARALLAXES_MAKE_VERSION(major, minor, patch) ((major) * 10000 + (minor) * 100 + (patch))
#define PARALLAXES_VERSION \
    PARALLAXES_MAKE_VERSION(PARALLAXES_VERSION_MAJOR, PARALLAXES_VERSION_MINOR, PARALLAXES_VERSION_PATCH)
