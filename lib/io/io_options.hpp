// The options of the output layer (files, statistics, checkpoint and restart) and of the aries program itself,
// declared once (core/option_decl.hpp).
#pragma once

#include "core/option_decl.hpp"

namespace aries::io::opt {

using core::flagOption;
using core::intOption;
using core::OptionDecl;
using core::textOption;

// ---- output ----
inline constexpr OptionDecl output =
    textOption("-output", "DIR/NAME",
               "writes DIR/NAME.h5 (mesh), one DIR/NAME.steps/NAME_<step>.h5 per output step and DIR/NAME.xmf for "
               "ParaView (see Output files below)")
        .otherwise("none");
inline constexpr OptionDecl outputEvery =
    intOption("-output_every", "K", "write every K steps (the initial state and the last step are always written)")
        .byDefault("1")
        .atLeast(1);
inline constexpr OptionDecl outputFields =
    textOption("-output_fields", "f,...|all",
               "the fields written at every output step (table below); all = every field (velocity only with "
               "-integrator beuler)")
        .byDefault("alpha,energy_density,fiber,J,von_mises");
inline constexpr OptionDecl stats =
    textOption("-stats", "FILE.csv", "one row per step: Newton updates, linear solves, CG iterations, time, energy, "
                                     "reason, ... (columns below)")
        .otherwise("none");
inline constexpr OptionDecl newtonHistory =
    textOption("-newton_history", "FILE.csv", "one row per Newton iteration (columns below)").otherwise("none");
inline constexpr OptionDecl reactions =
    textOption("-reactions", "FILE.csv",
               "per step and clamped set: step,time,set,fx,fy,fz, the summed internal force on the set's vertices")
        .otherwise("none");
inline constexpr OptionDecl version =
    flagOption("-version",
               "print the aries version and the git commit it was built from, then exit (also in every output file "
               "and the stats header)")
        .byDefault("false");
inline constexpr OptionDecl strict =
    flagOption("-strict",
               "unknown or unused options are an error (checked after setup and at the end); without it they are one "
               "warning line after setup")
        .byDefault("false");

inline constexpr const OptionDecl *kOutputOptions[] = {&output,    &outputEvery, &outputFields, &stats,
                                                       &newtonHistory, &reactions, &version,      &strict};

// ---- checkpoint and restart ----
inline constexpr OptionDecl checkpointEvery =
    intOption("-checkpoint_every", "K",
              "after every K-th step write the full state to one HDF5 file, atomically (0: off)")
        .byDefault("0")
        .atLeast(0);
inline constexpr OptionDecl checkpoint =
    textOption("-checkpoint", "FILE.h5", "where the checkpoint goes (overwritten each time)")
        .otherwise("DIR/NAME.checkpoint.h5 with -output, else checkpoint.h5");
inline constexpr OptionDecl restart =
    textOption("-restart", "FILE.h5",
               "continue from a checkpoint: run with the same options and add -restart; any number of ranks")
        .otherwise("none");

inline constexpr const OptionDecl *kCheckpointOptions[] = {&checkpointEvery, &checkpoint, &restart};

}  // namespace aries::io::opt
