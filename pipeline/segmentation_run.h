// A segmentation network run over a dataset's photos, as `rigsim segment` and `calibrate
// --segmenter` run it: the network and its photos (segmentation/segment_dataset.h, whose types this
// header brings along so that the commands need nothing below the pipeline), the files such a run
// reads, and the text that says what it did. No printing: the caller shows the text.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "dataset/output_folder.h"
#include "segmentation/segment_dataset.h"
#include "segmentation/segmenter.h"

namespace rigsim {

// The files a network run reads, named by `model_option` ("--model", "--segmenter"), for an
// output folder that must not replace them: the model, and the class table when it is a file.
std::vector<CommandInput> SegmenterInputs(const SegmenterOptions& options, const std::string& model_option);

// What a run did, in lines for the terminal: photos, model, classes and timing; the share of each
// class; and, on rendered data, the agreement with the true labels per class.
std::string FormatSegmentationSummary(const SegmentDatasetSummary& summary, const Segmenter& segmenter);

}  // namespace rigsim
