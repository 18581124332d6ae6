#!/usr/bin/env bash
# Builds the tests a second time with AddressSanitizer and UndefinedBehaviorSanitizer
# (any report fails) and runs them, except the heavy ones listed below: whole scenes simulated
# for seconds, stiff or large cloths, every shipped scene run, viewed or rendered by the command
# (minutes each here). They run the same code paths as the short tests, ten times slower under
# the sanitizers, and the Release run covers them.
set -euo pipefail
cd "$(dirname "$0")/.."
# -O1 -g1: line tables for the reports' stacks without full debug information; this compiles
# about twice as fast as -O2 -g on 2 cores (7 minutes instead of 12), and the tests run as fast.
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" -DDRAPE_SANITIZE=address,undefined -DDRAPE_BUILD_BENCH=OFF -DDRAPE_PYTHON=OFF >/dev/null
cmake --build build-asan --parallel "$(nproc)"
heavy='HangScene|SphereScene|GroundScene|AStableFreeFall|StiffAtTheFrameStep|LongRangeOnHang|StaticEquilibrium|AStiffScene|SinglePrecision|ADiscDrapedOverASphere|SameBitsTwiceAndOnOneThreadOrTwo|EachShippedSceneAndMethodHashesTheSameTwice|AutoOnShippedScene|Elastica.AClamped|ATwistedStripNeverCrossesItself|NoFrameEndsWithCrossingTriangles|APileComesToRest|AMeshSphereDrapesLikeTheAnalyticSphere|AMovingBoxGivesTheSameBits|LabCantilever.Measures|LabCusick.StifferDrapes|LabCusick.TheDrapeCoefficientSettles|EveryShippedScene|SaysWhenTheSpringsOwnStretch|MaterialConvergence|AreaDrag.TerminalSpeed|AFastBallPushesTheCurtain|ABoxsEdgesAndCornersNeverPierce'
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure --parallel "$(nproc)" --timeout 900 -E "$heavy"
