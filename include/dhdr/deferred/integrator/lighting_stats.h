// What the lighting pass (lighting.h) counted: lights evaluated, pixels, rays.
#pragma once

namespace dhdr {

struct LightingStats {
    // Lights considered, summed over covered pixels: those in the pixel's tile list whose
    // depth slice matches (every light with bruteForce).
    long long lightEvaluations = 0;
    // Of those, the lights whose range actually reaches the pixel's surface point.
    long long lightsReaching = 0;
    long long coveredPixels = 0;
    // Entries of all the tile lists.
    long long tileListEntries = 0;
    long long shadowRays = 0, aoRays = 0;
    // Rays of a shadow catcher's bounce light: to the objects, and their shadow rays.
    long long bounceRays = 0;
    // Rays of the reference path tracer (--gi path): its paths' and their shadow rays.
    long long pathRays = 0;
    // Rays of the specular indirect light, and their hits' shadow rays.
    long long specularRays = 0;
    // Covered samples whose normal was no direction (zero, NaN, ±Inf) and was replaced
    // (GBufferView::at): the tools warn.
    long long repairedNormals = 0;

    LightingStats& operator+=(const LightingStats& o) {
        lightEvaluations += o.lightEvaluations;
        lightsReaching += o.lightsReaching;
        coveredPixels += o.coveredPixels;
        tileListEntries += o.tileListEntries;
        shadowRays += o.shadowRays;
        aoRays += o.aoRays;
        bounceRays += o.bounceRays;
        pathRays += o.pathRays;
        specularRays += o.specularRays;
        repairedNormals += o.repairedNormals;
        return *this;
    }
};

} // namespace dhdr
