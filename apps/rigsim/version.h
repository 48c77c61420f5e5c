#pragma once
// Set by CMake from project(VERSION); recorded in frames.json.
#ifndef RIGSIM_VERSION_STRING
#define RIGSIM_VERSION_STRING "unknown"
#endif
