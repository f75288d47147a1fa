// Implementation of the OpenSubdiv shim (see shim.h).
#include "shim.h"

#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <opensubdiv/version.h>

using namespace OpenSubdiv;

namespace {

char* copy_message(const std::string& s) {
  char* out = static_cast<char*>(std::malloc(s.size() + 1));
  if (out) std::memcpy(out, s.c_str(), s.size() + 1);
  return out;
}

// OpenSubdiv reports topology problems through a global callback; surfkit keeps the last
// message so a failing factory call can say why.
thread_local std::string last_osd_error;
void on_osd_error(Far::ErrorType, const char* message) { last_osd_error = message ? message : ""; }
void on_osd_warning(const char* message) { last_osd_error = message ? message : ""; }

void install_callbacks() {
  Far::SetErrorCallback(on_osd_error);
  Far::SetWarningCallback(on_osd_warning);
}

template <class F>
int guarded(char** error, F&& body) {
  try {
    install_callbacks();
    last_osd_error.clear();
    std::string msg = body();
    if (msg.empty()) return 0;
    if (error) *error = copy_message(msg);
    return 1;
  } catch (const std::exception& e) {
    if (error) *error = copy_message(std::string("OpenSubdiv: ") + e.what());
    return 2;
  } catch (...) {
    if (error) *error = copy_message("OpenSubdiv: unknown C++ exception");
    return 2;
  }
}

}  // namespace

extern "C" int surfkit_osd_version(void) { return OPENSUBDIV_VERSION_NUMBER; }

extern "C" int surfkit_osd_self_test(char** error) {
  return guarded(error, []() -> std::string {
    static const int verts_per_face[6] = {4, 4, 4, 4, 4, 4};
    static const int indices[24] = {0, 1, 3, 2, 2, 3, 5, 4, 4, 5, 7, 6,
                                    6, 7, 1, 0, 1, 7, 5, 3, 6, 0, 2, 4};
    Far::TopologyDescriptor desc;
    desc.numVertices = 8;
    desc.numFaces = 6;
    desc.numVertsPerFace = verts_per_face;
    desc.vertIndicesPerFace = indices;
    typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> Factory;
    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    Far::TopologyRefiner* refiner =
        Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc));
    if (!refiner) return "TopologyRefinerFactory failed: " + last_osd_error;
    refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(1));
    int nv = refiner->GetLevel(1).GetNumVertices();
    int nf = refiner->GetLevel(1).GetNumFaces();
    delete refiner;
    if (nv != 26 || nf != 24)
      return "cube refined to " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
             " faces, expected 26 and 24";
    return "";
  });
}

extern "C" void surfkit_osd_free_message(char* message) { std::free(message); }
