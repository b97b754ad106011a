// The osdmra tool's commands, by family; each takes the arguments after its name and
// returns the exit status. main.cpp dispatches to them.
#pragma once

#include <string>
#include <vector>

namespace osdmra::cli {

using Argv = std::vector<std::string>;

// Meshes (mesh_commands.cpp).
int cmdInfo(const Argv& argv);
int cmdSubdivide(const Argv& argv);
int cmdShape(const Argv& argv);
int cmdRemesh(const Argv& argv);

// Analysis and synthesis (analysis_commands.cpp).
int cmdAnalyze(const Argv& argv);
int cmdSynthesize(const Argv& argv);
int cmdMask(const Argv& argv);
int cmdOrthogonality(const Argv& argv);

// Levels of detail and studies of them (lod_commands.cpp).
int cmdLod(const Argv& argv);
int cmdSweep(const Argv& argv);
int cmdDemo(const Argv& argv);

// The progressive geometry codec (codec_commands.cpp).
int cmdCompress(const Argv& argv);
int cmdDecompress(const Argv& argv);

}  // namespace osdmra::cli
