#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer (docs/hardening.md).
# One clang build in build-san/ serves this check and the fuzzers (scripts/check_fuzz.sh):
# -DPATLAB_FUZZ=ON compiles every library, the tool, the tests and the harnesses with
# -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all, so the first report fails
# its test (leak checking on). Every test ctest knows runs as in the Release build, but those listed below.
# CI runs it from scripts/test.sh; locally after scripts/setup.sh. ccache is used when present.
# Other sanitizers (TSan, MSan) use -DPATLAB_SANITIZE=... in a build of their own: docs/hardening.md.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${PATLAB_SANITIZER_BUILD_DIR:-build-san}"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
start=$SECONDS
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DPATLAB_FUZZ=ON "${launcher[@]}" >/dev/null
cmake --build "$build" -j"$(nproc)"
built=$SECONDS
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# Every test runs here but the few below, those whose numbers come from arithmetic that differs
# between compilers in the last bits included: reproduce --check's per-column rules accept
# another compiler's knife-edge cells (docs/reproduce.md), and the calibration tests check each
# fit against its own covariance (docs/calibrate.md).
# Release only: the slowest tests (10-20x slower here; in Release, 42 tests of over 2 s take 95 %
# of the suite's test time), each of which repeats on more data or other cameras the code
# paths a test that does run here already takes. Every suite keeps at least one test here.
release_only=(
  # fits every model of the ssl family; FamilySearch.OneModelIsTheAutomaticCalibration runs the
  # same screen and fits here
  'FamilySearch.TheScreenKeepsWhatFittingEveryModelKeeps'
  'FamilySearch.WhereTheLinesDoNotDecideTheRivalsAreKept'
  # fresh seed 205's lines, one model's view lent to another: every family search here scores
  # every model's views against the others' lines (FamilySearch.OneModelIsTheAutomaticCalibration)
  'FamilySearch.AViewAnotherModelsSearchFoundIsLentWhereItExplainsMore'
  # fresh seed 334's lines and their runners-up: SetupCamera.TheRobotsOverruleALinesCamera-
  # NoneDecodesThrough runs the same search, and weighs its runner-up, here
  'FamilySearch.TheRunnersUpAreTheCamerasTheLinesDecideAgainstNarrowly'
  # the family search on rendered frames of three models: FamilySearch above covers it
  'Models/FamilyRendered.KeepsTheTrueModelAndItsCamera/"ssl-2009"'
  'Models/FamilyRendered.KeepsTheTrueModelAndItsCamera/"ssl-2015"'
  'Models/FamilyRendered.KeepsTheTrueModelAndItsCamera/"ssl-2018"'
  # the automatic calibration on more rendered cameras: seed 5 and At3000mm run here
  'Seeds/AutoCalibrateRendered.MapsTheFloorWithin5MmAndKnowsItsError/1'
  'Seeds/AutoCalibrateRendered.MapsTheFloorWithin5MmAndKnowsItsError/2'
  'Seeds/AutoCalibrateRendered.MapsTheFloorWithin5MmAndKnowsItsError/3'
  'Seeds/AutoCalibrateRendered.MapsTheFloorWithin5MmAndKnowsItsError/4'
  'Seeds/AutoCalibrateRendered.MapsTheFloorWithin5MmAndKnowsItsError/6'
  'Cameras/HeldOutError.AgreesWithTheTruthOrSaysItIsBelowItsResolution/At3300mm'
  'Cameras/HeldOutError.AgreesWithTheTruthOrSaysItIsBelowItsResolution/At3800mm'
  'Cameras/HeldOutError.AgreesWithTheTruthOrSaysItIsBelowItsResolution/At4100mm'
  'Cameras/HeldOutError.AgreesWithTheTruthOrSaysItIsBelowItsResolution/At4500mm'
  # fits eight cameras from the floor's lines alone; AMeasuredCameraHeightDeterminesTheFocalLength
  # fits the same eight here, with a measured height
  'Calibrate.TheFloorAloneMapsTheFloorAndSaysWhatItCannotKnow'
  # refits a camera 200 times through the fit Calibrate's other tests run here
  'Calibrate.TheMappingCovarianceIsTheSpreadOfRefits'
  # the fit with robots' patterns on more random cameras: AMeasuredCameraHeightDeterminesTheFocal-
  # Length fits field and robots here, and so does every setup test that decodes robots
  'Calibrate.RecoversRandomCamerasFromFieldAndRobots'
  # setup's robot paths on more rendered scenes: TheRobotsACornerAndTheHeightFixTheCamera... (the
  # robots place the field), cli.SetupCli.RenderedFrameToDetections... (the robots set the
  # height) and LandmarksReplaceTheLines run here
  'SetupCamera.TheRobotsDecideWhereTheLinesDoNot'
  'SetupCamera.TheRobotsSetTheCameraHeightTheLinesLeaveOpen'
  'SetupCamera.ACornerAndTenRobotsWithoutTheHeightDoNotFixTheCamera'
  # a model named alone and its lenders (rendered seeds 3 and 205): every setup test that names
  # a model runs the lenders' search, their lent views and the fit as the named model here
  # (cli.SetupCli.RenderedFrameToDetectionsWithEveryRobotAndTheFloorWithin5Mm, ssl-2009 named)
  'SetupCamera.AModelNamedAloneIsFittedFromItsFamilysViews'
  'FamilySearch.AModelNamedAloneBorrowsTheViewsOfItsLenders'
  # fresh seed 332's corner placed by the robots, refused against a placement of another model:
  # TheRobotsACornerAndTheHeightFix... runs the placements and their refusal rule here
  'SetupCamera.ACornerPlacementAnotherExplainsNearlyAsWellIsRefused'
  # fresh seed 406's small patches, the floor scales scanned through a second colour fit:
  # TheRobotsACornerAndTheHeightFix... runs both fits and both scans here
  'SetupCamera.SmallPatchesDecodeWhereTheColoursAreFittedForThem'
  'SetupCamera.CamerasNeitherTheLinesNorTheRobotsDecideAreRefused'
  # few-lines view 8 again, with its height given: RobotsDecideBetweenCamerasOnlyWhereAHeightIs-
  # Measured runs the same scene and cameras here, CreditedRobots.* the given height's rule
  'SetupCamera.AGivenHeightDecidesBetweenCamerasOnlyWhereTheLinesFixTheFocalLength'
  # few-lines view 5 handed to the robots' path: FocalAtItsBound.* runs the rule here, and
  # TheRobotsACornerAndTheHeightFix... the robots' path
  'SetupCamera.LinesThatFitOnlyAtTheFocalLengthsBoundLeaveTheCameraToTheRobots'
  # fresh seed 89's three cameras and dim patches: every setup test that fits colours runs the six
  # blobs' fits here, RobotsDecideBetweenCamerasOnlyWhereAHeightIsMeasured the rivals' path
  'SetupCamera.DullPatchesNearTheCarpetsColourStandOutAtTheLowerThreshold'
  # fresh seed 20's centre view, decided by a piece of touch line: FamilySearch.ExclusiveLine-
  # PixelsAreThoseOneCameraAloneExplains runs the rule here on the same camera's lines
  'SetupCamera.APieceOfTouchLineInACornerDecidesACentreView'
  # fresh seed 196's rival camera that sees above the horizon: AutoCalibrateHorizon.* runs the
  # check here on that camera and on random ones
  'SetupCamera.ACameraThatSeesAboveTheHorizonIsNoFieldCamera'
  # fresh seed 263's centre view, whose repeated views leave their place to the true camera:
  # every automatic calibration runs that rule here, and CamerasNeitherTheLinesNorTheRobots-
  # DecideAreRefused the refusal it leads to
  'SetupCamera.AViewThatRepeatsAFittedCameraLeavesItsPlaceToTheNext'
  # the automatic calibration's fits with and without the settled stop on seed 58's lines: every
  # automatic calibration runs here settled
  'SettledFit.StopsTheCrawlAlongTheValleyAtTheSameFloorMap'
  # fresh seed 122's coarse fit with the robots, kept: every setup test that decodes robots runs
  # the same fit here, CreditedRobots.* the credit such a fit gives
  'SetupCamera.LinesThatDoNotMeasureTheHeightLeaveItToTheRobotsHoweverCoarse'
  # the rendered SSL frame again, with its height given: cli.SetupCli.RenderedFrameToDetections...
  # runs the same commands on it here, TheRobotsACornerAndTheHeightFix... a given height
  'cli.SetupCli.TheGivenCameraHeightIsTheCalibrations'
  # a twice-larger rendered frame set up binned 2 x 2 and 3 x 3: FrameDetector.BinnedFrames... runs
  # the binned detection here, BinImage.* and CameraModel.AResized... its pieces, and
  # cli.SetupCli.RenderedFrameToDetections... the same setup on the frame's own size
  'cli.SetupCli.FramesOverAThousandPixelsAreBinnedAndDetectedAlike'
  # setup and detect on the real frames at more exposures and through the family of four VSS
  # designs; cli.SetupRealCli.VssFrameWithNoHandWrittenFile and Ssl2008Frame... run here
  'cli.SetupRealCli.ColoursFittedOnOneExposureHoldOnADarkerAndABrighterOne'
  'cli.SetupRealCli.VssFrameWithTheShippedFamilySettings'
  # setup and detect on rendered frames of every shipped VSS design; the same commands run here
  # on the rendered SSL frame (cli.SetupCli.*) and on the real VSS frame
  'cli.VssDesignsCli.EveryShippedDesignTeamAndIdOnRenderedFrames'
  # ten commands into a relative out folder; each command's own CLI tests run it here, and
  # ACommandThatFailsBeforeItsCommitLeavesNoFolderItMade runs the same ten on a full disk
  'cli.RelativeOutCli.EveryCommandMakesARelativeOutFolderThatDoesNotExistYet'
  # fresh seed 59's one straight line, refused: every setup test here matches and measures the
  # lines' arcs, TheRobotsACornerAndTheHeightFix... among them, and refuses through the same report
  'SetupCamera.OneStraightLineFixesNoCameraThoughItFitsAPieceOfArc'
  # the real SSL frame again from another segmentation scale: Ssl2008FrameWithNoHandWrittenFile
  # runs the same setup, with its scan of scales, here
  'cli.SetupRealCli.Ssl2008FrameFromASegmentationScaleThatJoinsItsPatches'
  # setup --explain on the rendered SSL frame: cli.SetupCli.RenderedFrameToDetections... runs the
  # same setup here, ExplainCli's other tests the diagnoses through detect --explain
  'cli.ExplainCli.SetupExplainsEveryKeyAfterTheRobots'
  # the second narrow view: the first (Over1500x0At3000mm) runs the same search here
  'PosHalf/NarrowView.IsCalibratedTheRightWayRound/Over1700x100At2800mm'
  # replays every trial of a run; Replay.SampledTrialsOfEveryEstimatorAndNoiseModelAreTheRunsBits
  # replays a sample of each estimator and noise model here
  'Replay.EveryTrialReplayedGivesTheRunsStatistics'
  # reruns every committed experiment of the paper; the comparison's own tests (Reproduce.*,
  # ReproduceCompare.*) and the command's malformed input (CliReproduce...) run here
  'cli.ReproduceCli.CheckPassesOnTheCommittedResultsAndNamesAnEditedFile'
)
exclude=$(printf '%s\n' "${release_only[@]}" | sed 's/[][\\.*^$+?(){}|/]/\\&/g; s/.*/^&$/' | paste -sd'|')
tests=$(ctest --test-dir "$build" -N -E "$exclude" | sed -n 's/^Total Tests: //p')
ctest --test-dir "$build" --output-on-failure -j"$(nproc)" -E "$exclude"
echo "check_sanitizers: ${tests} tests clean under ASan + UBSan (${#release_only[@]} run in Release only); build $((built - start)) s, tests $((SECONDS - built)) s"
