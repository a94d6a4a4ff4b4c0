// Writes the bundled hole-plate example (README.md in this folder):
//   make_hole_plate_example MODEL.json OUT_DIR
// MODEL.json is examples/cmm_model.json (its kinematics section gives the truth's distribution).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "hole_plate_example.h"
#include "vcmm/errormodel/digital_model.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: make_hole_plate_example MODEL.json OUT_DIR\n";
    return 2;
  }
  try {
    const vcmm::errormodel::DigitalModel model = vcmm::errormodel::read_digital_model_file(argv[1]);
    const std::filesystem::path dir(argv[2]);
    for (const auto& [name, content] : vcmm::examples::hole_plate_example_files(model)) {
      std::ofstream f(dir / name, std::ios::binary | std::ios::trunc);
      f << content;
      if (!f) {
        std::cerr << "make_hole_plate_example: cannot write " << (dir / name).string() << "\n";
        return 1;
      }
      std::cout << "wrote " << (dir / name).string() << "\n";
    }
    return 0;
  } catch (const std::exception& ex) {
    std::cerr << "make_hole_plate_example: " << ex.what() << "\n";
    return 1;
  }
}
