#!/usr/bin/env bash
# Builds the tests a second time with AddressSanitizer and UndefinedBehaviorSanitizer
# (scripts/sanitized_build.sh; any report fails) and runs them, except the heavy ones listed
# below: whole scenes simulated for seconds, stiff or large cloths, every shipped scene run,
# viewed or rendered by the command (minutes each here), and the slowest of a family whose
# others run. They run the same code paths as the short tests, ten times slower under
# the sanitizers, and the Release run covers them. Each entry is a CTest regular expression;
# together they keep this stage's tests near 5 minutes on CI's 2 cores (.ci/run's 30 in all).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/sanitized_build.sh
heavy=(
  HangScene SphereScene GroundScene AStableFreeFall StiffAtTheFrameStep LongRangeOnHang
  StaticEquilibrium AStiffScene SinglePrecision ADiscDrapedOverASphere
  SameBitsTwiceAndOnOneThreadOrTwo EachShippedSceneAndMethodHashesTheSameTwice AutoOnShippedScene
  Elastica.AClamped ATwistedStripNeverCrossesItself NoFrameEndsWithCrossingTriangles
  AMeshSphereDrapesLikeTheAnalyticSphere AMovingBoxGivesTheSameBits
  LabCantilever.Measures LabCusick.StifferDrapes LabCusick.TheDrapeCoefficientSettles
  EveryShippedScene SaysWhenTheSpringsOwnStretch MaterialConvergence AreaDrag.TerminalSpeed
  AFastBallPushesTheCurtain ABoxsEdgesAndCornersNeverPierce
  'AnOpenSheetsRimNeverCutsThroughTheCloth/(symplectic|auto|implicit) ' AirDrag.ReachesTerminalSpeed
  CrumpledClothMatchesBruteForce MaterialDamping.AStripsSwing
  'ASheetFallingFastOntoASmallStillBallNeverTunnelsThroughIt/(fast|symplectic|implicit) '
  'ASheetFallingFastOntoAThinStillPlateNeverPassesThroughIt/(fast|symplectic) '
  Determinism.TheThreadCountDoesNotChangeTheBits XpbdStiffSweeps XpbdLinePasses
  'SameSceneTwiceGivesBitIdenticalState/implicit '
  'SameBitsTwiceWithSpringsOnlyOneThreadCanSweep/implicit '
  'WindModels.WindMovesTheClothDownwind/aero ' AutoMethod.SettlesOnARestingCloth
  AClothTornByALinearisedStep TheShippedPileLiesStill APlateOutrunningItsSweepThroughTheCurtain
)
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure --parallel "$(nproc)" --timeout 900 -E "$(IFS="|"; echo "${heavy[*]}")"
