#include "segmentation/onnx_model_info.h"

#include <gtest/gtest.h>

#include "testing/onnx_builder.h"

namespace rigsim {
namespace {

OnnxConvModel TwoClasses() {
  OnnxConvModel m;
  m.weights = {{1, 0, 0}, {0, 1, 0}};
  m.bias = {0, 0};
  return m;
}

TEST(OnnxModelInfo, OpenInputSize) {
  const OnnxModelInfo info = ParseOnnxModelInfo(OnnxModelBytes(TwoClasses()));
  EXPECT_EQ(info.input_name, "image");
  EXPECT_EQ(info.input_shape, (std::vector<int64_t>{1, 3, -1, -1}));
  EXPECT_EQ(info.output_name, "scores");
  EXPECT_EQ(info.ir_version, 6);
}

TEST(OnnxModelInfo, FixedInputSizeAndArgmaxOutput) {
  OnnxConvModel m = TwoClasses();
  m.width = 16;
  m.height = 12;
  m.argmax = true;
  const OnnxModelInfo info = ParseOnnxModelInfo(OnnxModelBytes(m));
  EXPECT_EQ(info.input_shape, (std::vector<int64_t>{1, 3, 12, 16}));
  EXPECT_EQ(info.output_name, "classes");
}

TEST(OnnxModelInfo, RefusesWhatIsNoModel) {
  const std::string model = OnnxModelBytes(TwoClasses());
  EXPECT_THROW(ParseOnnxModelInfo(""), std::runtime_error);
  EXPECT_THROW(ParseOnnxModelInfo("this is not a model\n"), std::runtime_error);
  EXPECT_THROW(ParseOnnxModelInfo(std::string_view(model).substr(0, model.size() / 2)), std::runtime_error);
  EXPECT_THROW(ParseOnnxModelInfo(std::string(64, '\xff')), std::runtime_error);
}

}  // namespace
}  // namespace rigsim
