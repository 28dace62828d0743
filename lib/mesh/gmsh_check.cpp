#include "mesh/gmsh_check.hpp"

#include "core/errors.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <unordered_map>
#include <set>
#include <sstream>
#include <unordered_set>
#include <vector>
#include <cstdlib>

namespace aries::fem {

using core::collectiveCheck;

namespace {

// Element types aries can read: gmsh 1 = 2-node line, 2 = 3-node triangle, 3 = 4-node quadrangle (the faces of
// hexahedra), 4 = 4-node tetrahedron, 5 = 8-node hexahedron, 15 = point, and the second-order simplices 8 = 3-node
// line, 9 = 6-node triangle, 11 = 10-node tetrahedron (read as their corners; -element p2 takes their edge nodes).
int nodesOfType(int type) {
  switch (type) {
    case 1: return 2;
    case 2: return 3;
    case 3: return 4;
    case 4: return 4;
    case 5: return 8;
    case 8: return 3;
    case 9: return 6;
    case 11: return 10;
    case 15: return 1;
    default: return -1;
  }
}

// The corners of an element: its first nodes (a second-order element lists its edge nodes after them).
int cornersOfType(int type) {
  switch (type) {
    case 8: return 2;
    case 9: return 3;
    case 11: return 4;
    default: return nodesOfType(type);
  }
}

// gmsh's 10-node tetrahedron: node 4 + k sits on the edge joining corners kGmshTet10Edges[k] (gmsh's node order).
constexpr int kGmshTet10Edges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};

const char *typeName(int type) {
  switch (type) {
    case 6: return "6-node prism";
    case 7: return "5-node pyramid";
    case 8: return "3-node second-order line";
    case 9: return "6-node second-order triangle";
    case 11: return "10-node second-order tetrahedron";
    default: return "element";
  }
}

// Reader::numbers: every number of the line is an integer (a tag, count or type), and the largest such integer.
constexpr size_t kAllColumns = static_cast<size_t>(-1);
constexpr double kMaxInteger = 2147483647.0;

class Reader {
 public:
  Reader(std::istream &in, std::string file) : in_(in), file_(std::move(file)) {}
  bool line(std::string *out) {
    while (std::getline(in_, *out)) {
      ++lineNo_;
      if (!out->empty() && out->back() == '\r') out->pop_back();
      return true;
    }
    return false;
  }
  // Reads the next line and splits it into numbers, the first integerColumns of which (tags, counts, types) must be
  // integers (integers() below); false (and an error) at end of file or on a bad number.
  bool numbers(std::vector<double> *v, const char *what, size_t integerColumns, long declared = -1, long index = -1) {
    std::string l;
    if (!line(&l)) return fail(std::string("file ends inside ") + what + " (truncated?)");
    if (!l.empty() && l[0] == '$') {
      if (declared >= 0)
        return fail(std::string(what) + " declares " + std::to_string(declared) + " entries but ends after " +
                    std::to_string(index) + " (wrong count?)");
      return fail(std::string(what) + " ends early at " + l);
    }
    v->clear();
    // Whitespace-separated tokens, each wholly a number (strtod in place: no stream or token copy per line; the
    // stream cost about a third of this pass on the 125k-tet box).
    const char *p = l.c_str();
    const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    while (true) {
      while (space(*p)) ++p;
      if (*p == '\0') break;
      char *end = nullptr;
      const double x = std::strtod(p, &end);
      if (end == p || !(*end == '\0' || space(*end))) {
        const char *stop = p;
        while (*stop != '\0' && !space(*stop)) ++stop;
        return fail("'" + std::string(p, stop) + "' is not a number in " + what);
      }
      v->push_back(x);
      p = end;
    }
    return integers(*v, what, 0, integerColumns);
  }
  // v[from, to) must be whole numbers of magnitude at most 2^31 - 1 (gmsh's tags, counts and types; larger ones are
  // not supported), so that converting them to int or long is defined.
  bool integers(const std::vector<double> &v, const char *what, size_t from, size_t to = kAllColumns) {
    for (size_t k = from; k < std::min(to, v.size()); ++k)
      if (!(std::abs(v[k]) <= kMaxInteger) || v[k] != std::floor(v[k])) {
        std::ostringstream o;
        o << "number " << k + 1 << " of a " << what << " line, " << std::setprecision(15) << v[k]
          << ", is not an integer between -2147483647 and 2147483647 (a tag, count or type)";
        return fail(o.str());
      }
    return true;
  }
  bool expect(const std::string &marker) {
    std::string l;
    if (!line(&l)) return fail("file ends before " + marker + " (truncated?)");
    if (l != marker) return fail("expected " + marker + ", found '" + l.substr(0, 40) + "'");
    return true;
  }
  bool fail(const std::string &msg) {
    if (error_.empty()) {
      std::ostringstream o;
      o << "mesh file '" << file_ << "' line " << lineNo_ << ": " << msg;
      error_ = o.str();
    }
    return false;
  }
  const std::string &error() const { return error_; }

 private:
  std::istream &in_;
  std::string file_, error_;
  long lineNo_ = 0;
};

bool checkElementType(Reader &r, int type) {
  if (nodesOfType(type) > 0) return true;
  std::ostringstream o;
  o << "unsupported element type " << type << " (" << typeName(type)
    << "); aries reads tetrahedra (4 or 10 nodes), triangles and trilinear hexahedra (with lines, triangles, "
         "quadrangles and points for boundary groups)";
  return r.fail(o.str());
}

int dimensionOfType(int type) {
  switch (type) {
    case 15: return 0;
    case 1:
    case 8: return 1;
    case 2:
    case 3:
    case 9: return 2;
    default: return 3;
  }
}

// What the parsers record: the node tags (so elements can be checked against them) in file order, the nodes' bounding
// box, and, when asked (`facets`), what GmshFacets needs: each node's coordinates, which nodes are element corners,
// the physical tags of the MSH 4 entities and the tagged triangles and quadrangles.
struct NodeData {
  std::unordered_map<long, long> index;  // node tag -> position in the file
  unsigned elementTypes = 0;             // bit per gmsh element type seen (types < 32)
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  GmshFacets *facets = nullptr;          // collect for it (rank 0), or not
  std::vector<double> xyz;               // per node in file order (collecting)
  std::vector<char> corner;              // per node: a corner of some element (collecting)
  std::map<std::pair<int, int>, int> entityTag;  // MSH 4 (dim, entity) -> its first physical tag, -1 for none
  struct Tagged {
    int dim, tag, n;
    std::array<long, 4> node;  // positions in the file
  };
  std::vector<Tagged> tagged;  // triangles and quadrangles with a physical tag (collecting)
  struct EdgeNode {
    long a, b, node;  // corners and the edge node: positions in the file
  };
  std::vector<EdgeNode> edgeNodes;  // of every 10-node tetrahedron (collecting)

  bool addNode(long tag, double x, double y, double z) {
    const double p[3] = {x, y, z};
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], p[d]);
      hi[d] = std::max(hi[d], p[d]);
    }
    if (!index.emplace(tag, static_cast<long>(index.size())).second) return false;
    if (facets) xyz.insert(xyz.end(), p, p + 3);
    return true;
  }
  // An element of `type` with its node tags (all defined) and its first physical tag (hasTag).
  void addElement(int type, bool hasTag, int tag, const double *nodeTags) {
    if (!facets) return;
    if (corner.size() != index.size()) corner.assign(index.size(), 0);
    facets->cellDim = std::max(facets->cellDim, dimensionOfType(type));
    const int corners = cornersOfType(type);
    Tagged t{dimensionOfType(type), tag, corners, {}};
    for (int k = 0; k < corners; ++k) {
      const long i = index.at(static_cast<long>(nodeTags[k]));
      corner[i] = 1;
      if (k < 4) t.node[k] = i;
    }
    if (hasTag && t.dim == 2 && corners <= 4) tagged.push_back(t);  // the faces of a 3D mesh
    if (type == 11)
      for (int k = 0; k < 6; ++k)
        edgeNodes.push_back({index.at(static_cast<long>(nodeTags[kGmshTet10Edges[k][0]])),
                             index.at(static_cast<long>(nodeTags[kGmshTet10Edges[k][1]])),
                             index.at(static_cast<long>(nodeTags[4 + k]))});
  }
  GmshFacts facts() const {
    return GmshFacts{true, hi[2] - lo[2], std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]})};
  }
  // The facets PETSc 3.18's reader labels: elements one dimension below the cells ("Face Sets"; it labels no lines
  // in 3D), their corners numbered as PETSc numbers its vertices.
  // The edge nodes of the 10-node tetrahedra, by the same numbering, once per edge.
  void finishFacets() {
    if (!facets) return;
    if (corner.size() != index.size()) corner.assign(index.size(), 0);
    std::vector<long> vertexOf(corner.size(), -1);
    long count = 0;
    for (size_t i = 0; i < corner.size(); ++i)
      if (corner[i]) vertexOf[i] = count++;
    facets->numVertices = count;
    for (const EdgeNode &e : edgeNodes) {
      GmshFacets::EdgeNode n;
      n.a = std::min(vertexOf[e.a], vertexOf[e.b]);
      n.b = std::max(vertexOf[e.a], vertexOf[e.b]);
      for (int d = 0; d < 3; ++d) n.x[d] = xyz[3 * e.node + d];
      facets->edgeNodes.push_back(n);
    }
    std::sort(facets->edgeNodes.begin(), facets->edgeNodes.end(),
              [](const GmshFacets::EdgeNode &p, const GmshFacets::EdgeNode &q) {
                return p.a != q.a ? p.a < q.a : p.b < q.b;
              });
    facets->edgeNodes.erase(std::unique(facets->edgeNodes.begin(), facets->edgeNodes.end(),
                                        [](const GmshFacets::EdgeNode &p, const GmshFacets::EdgeNode &q) {
                                          return p.a == q.a && p.b == q.b && p.x == q.x;  // two nodes on one edge stay
                                        }),
                            facets->edgeNodes.end());
    if (!facets->known) return;
    const int cellDim = facets->cellDim;
    for (const Tagged &t : tagged) {
      if (t.dim != cellDim - 1) continue;
      GmshFacets::Facet f;
      f.dim = t.dim;
      f.tag = t.tag;
      f.numCorners = t.n;
      for (int k = 0; k < t.n; ++k) {
        f.vertex[k] = vertexOf[t.node[k]];
        for (int d = 0; d < 3; ++d) f.corner[3 * k + d] = xyz[3 * t.node[k] + d];
      }
      facets->facets.push_back(f);
    }
  }
};

// Boundary groups match the cells: quadrangles are faces of hexahedra, triangles (as boundary faces) of tetrahedra.
bool checkBoundaryTypes(Reader &r, const NodeData &nodes) {
  const bool quads = nodes.elementTypes & (1u << 3), hexes = nodes.elementTypes & (1u << 5);
  const bool triangles = nodes.elementTypes & (1u << 2);
  if (quads && !hexes)
    return r.fail("quadrangles (element type 3) are read as faces of hexahedra, and the file has no hexahedra");
  if (hexes && triangles)
    return r.fail("triangles (element type 2) in a file of hexahedra: its boundary groups must be quadrangles");
  return true;
}

// One parser per section and format version.
using SectionParser = bool (*)(Reader &r, NodeData *nodes);

bool nodes2(Reader &r, NodeData *nodes) {
  std::vector<double> v;
  if (!r.numbers(&v, "$Nodes", kAllColumns) || v.size() != 1)
    return r.fail("expected the number of nodes after $Nodes");
  const long n = static_cast<long>(v[0]);
  for (long i = 0; i < n; ++i) {
    if (!r.numbers(&v, "$Nodes", 1, n, i)) return false;
    if (v.size() != 4) return r.fail("a node line needs 4 numbers (id x y z)");
    if (!nodes->addNode(static_cast<long>(v[0]), v[1], v[2], v[3]))
      return r.fail("node " + std::to_string((long)v[0]) + " is defined twice");
  }
  if (!r.expect("$EndNodes")) return r.fail("$Nodes declares " + std::to_string(n) + " nodes but has more or fewer");
  return true;
}

bool elements2(Reader &r, NodeData *nodes) {
  std::vector<double> v;
  if (!r.numbers(&v, "$Elements", kAllColumns) || v.size() != 1)
    return r.fail("expected the number of elements after $Elements");
  const long n = static_cast<long>(v[0]);
  for (long i = 0; i < n; ++i) {
    if (!r.numbers(&v, "$Elements", kAllColumns, n, i)) return false;
    if (v.size() < 3) return r.fail("an element line needs id, type, number of tags, tags and nodes");
    const int type = static_cast<int>(v[1]), ntags = static_cast<int>(v[2]);
    if (!checkElementType(r, type)) return false;
    if (ntags < 0) return r.fail("element " + std::to_string((long)v[0]) + " has a negative number of tags");
    nodes->elementTypes |= 1u << type;
    const size_t expected = 3 + static_cast<size_t>(ntags) + static_cast<size_t>(nodesOfType(type));
    if (v.size() != expected)
      return r.fail("element " + std::to_string((long)v[0]) + " has " + std::to_string(v.size()) +
                    " numbers, expected " + std::to_string(expected));
    for (size_t k = 3 + ntags; k < v.size(); ++k)
      if (!nodes->index.count(static_cast<long>(v[k])))
        return r.fail("element " + std::to_string((long)v[0]) + " uses node " + std::to_string((long)v[k]) +
                      ", which is not defined");
    nodes->addElement(type, ntags > 0, ntags > 0 ? static_cast<int>(v[3]) : 0, v.data() + 3 + ntags);
  }
  if (!r.expect("$EndElements"))
    return r.fail("$Elements declares " + std::to_string(n) + " elements but has more or fewer");
  return checkBoundaryTypes(r, *nodes);
}

bool nodes4(Reader &r, NodeData *nodes) {
  std::vector<double> v;
  if (!r.numbers(&v, "$Nodes", kAllColumns) || v.size() != 4)
    return r.fail("expected 'numBlocks numNodes minTag maxTag' after $Nodes");
  const long blocks = static_cast<long>(v[0]), total = static_cast<long>(v[1]);
  long seen = 0;
  for (long b = 0; b < blocks; ++b) {
    if (!r.numbers(&v, "$Nodes", kAllColumns) || v.size() != 4)
      return r.fail("expected a node block header (dim tag parametric count)");
    if (v[2] != 0) return r.fail("parametric node coordinates are not supported");
    const long n = static_cast<long>(v[3]);
    std::vector<long> tags;
    for (long i = 0; i < n; ++i) {
      if (!r.numbers(&v, "$Nodes", kAllColumns) || v.size() != 1) return r.fail("expected a node tag");
      tags.push_back(static_cast<long>(v[0]));
    }
    for (long i = 0; i < n; ++i) {
      if (!r.numbers(&v, "$Nodes", 0) || v.size() != 3) return r.fail("expected x y z of a node");
      if (!nodes->addNode(tags[i], v[0], v[1], v[2])) return r.fail("node " + std::to_string(tags[i]) + " is defined twice");
    }
    seen += n;
  }
  if (seen != total) return r.fail("$Nodes declares " + std::to_string(total) + " nodes but its blocks have " + std::to_string(seen));
  return r.expect("$EndNodes");
}

bool elements4(Reader &r, NodeData *nodes) {
  std::vector<double> v;
  if (!r.numbers(&v, "$Elements", kAllColumns) || v.size() != 4)
    return r.fail("expected 'numBlocks numElements minTag maxTag' after $Elements");
  const long blocks = static_cast<long>(v[0]), total = static_cast<long>(v[1]);
  long seen = 0;
  for (long b = 0; b < blocks; ++b) {
    if (!r.numbers(&v, "$Elements", kAllColumns) || v.size() != 4)
      return r.fail("expected an element block header (dim tag type count)");
    const int type = static_cast<int>(v[2]);
    if (!checkElementType(r, type)) return false;
    nodes->elementTypes |= 1u << type;
    const long n = static_cast<long>(v[3]);
    // the block's physical tag: its entity's first ($Entities)
    const auto entity = nodes->entityTag.find({static_cast<int>(v[0]), static_cast<int>(v[1])});
    if (entity == nodes->entityTag.end() && nodes->facets) nodes->facets->known = false;
    const int tag = entity == nodes->entityTag.end() ? -1 : entity->second;
    for (long i = 0; i < n; ++i) {
      if (!r.numbers(&v, "$Elements", kAllColumns)) return false;
      if (v.size() != static_cast<size_t>(1 + nodesOfType(type))) return r.fail("element line with a wrong number of nodes");
      for (size_t k = 1; k < v.size(); ++k)
        if (!nodes->index.count(static_cast<long>(v[k]))) return r.fail("element uses undefined node " + std::to_string((long)v[k]));
      nodes->addElement(type, tag >= 0, tag, v.data() + 1);
    }
    seen += n;
  }
  if (seen != total)
    return r.fail("$Elements declares " + std::to_string(total) + " elements but its blocks have " + std::to_string(seen));
  return r.expect("$EndElements") && checkBoundaryTypes(r, *nodes);
}

// MSH 4.1 $Entities: the first physical tag of every entity (points: tag x y z numPhysical tags...; curves, surfaces
// and volumes: tag and a bounding box, numPhysical tags..., then their bounding entities).
bool entities4(Reader &r, NodeData *nodes) {
  std::vector<double> v;
  if (!r.numbers(&v, "$Entities", kAllColumns) || v.size() != 4)
    return r.fail("expected the four entity counts after $Entities");
  const long counts[4] = {static_cast<long>(v[0]), static_cast<long>(v[1]), static_cast<long>(v[2]),
                          static_cast<long>(v[3])};
  for (int dim = 0; dim < 4; ++dim)
    for (long i = 0; i < counts[dim]; ++i) {
      if (!r.numbers(&v, "$Entities", 1)) return false;
      const size_t at = dim == 0 ? 4 : 7;  // numPhysicalTags
      if (v.size() <= at) return r.fail("an entity line too short for its physical tags");
      if (!r.integers(v, "$Entities", at)) return false;
      if (v[at] < 0 || v.size() < at + 1 + static_cast<size_t>(v[at]))
        return r.fail("an entity line too short for its physical tags");
      const int first = v[at] > 0 ? static_cast<int>(v[at + 1]) : -1;
      nodes->entityTag[{dim, static_cast<int>(v[0])}] = first;
    }
  return r.expect("$EndEntities");
}

// Other sections ($PhysicalNames, ...) are skipped line by line; PETSc reads them.
bool validateSections(Reader &r, SectionParser parseNodes, SectionParser parseElements, NodeData *nodesOut,
                      SectionParser parseEntities = nullptr) {
  std::string l;
  NodeData &nodes = *nodesOut;
  bool sawNodes = false, sawElements = false;
  while (r.line(&l)) {
    if (l == "$Entities" && parseEntities) {
      if (!parseEntities(r, &nodes)) return false;
    } else if (l == "$Periodic" && nodes.facets) {
      nodes.facets->known = false;
    } else if (l == "$Nodes") {
      if (!parseNodes(r, &nodes)) return false;
      sawNodes = true;
    } else if (l == "$Elements") {
      if (!sawNodes) return r.fail("$Elements before $Nodes");
      if (!parseElements(r, &nodes)) return false;
      sawElements = true;
    }
  }
  if (!sawNodes) return r.fail("no $Nodes section");
  if (!sawElements) return r.fail("no $Elements section");
  return true;
}

std::string validateFile(const std::string &file, const std::string &option, GmshFacts *facts, GmshFacets *facets) {
  struct stat st;
  if (stat(file.c_str(), &st) != 0)
    return "mesh file '" + file + "' (" + option + ") does not exist or is not readable; generate scene meshes with "
           "meshes/generate.sh NAME";
  if (!S_ISREG(st.st_mode)) return "mesh file '" + file + "' (" + option + ") is not a regular file";
  const auto dot = file.find_last_of('.');
  if (dot == std::string::npos || file.substr(dot) != ".msh")
    return "mesh file '" + file + "' (" + option + ") must be a gmsh file with the extension .msh";
  std::ifstream in(file, std::ios::binary);
  if (!in) return "mesh file '" + file + "' (" + option + ") is not readable";
  Reader r(in, file);
  std::string l;
  if (!r.line(&l) || l != "$MeshFormat") {
    r.fail("not a gmsh file: it does not start with $MeshFormat");
    return r.error();
  }
  std::vector<double> v;
  if (!r.numbers(&v, "$MeshFormat", 0) || v.size() != 3 || !r.integers(v, "$MeshFormat", 1)) {
    r.fail("expected 'version file-type data-size' after $MeshFormat");
    return r.error();
  }
  const double version = v[0];
  const int fileType = static_cast<int>(v[1]);
  if (!(version >= 2.0 && version < 3.0) && !(version >= 4.1 && version < 5.0)) {
    std::ostringstream o;
    o << "unsupported gmsh format version " << v[0] << " (2.x and 4.1 are supported: save the mesh as MSH 4.1 or 2.2)";
    r.fail(o.str());
    return r.error();
  }
  if (fileType != 0) return {};  // binary: left to PETSc's reader
  if (!r.expect("$EndMeshFormat")) return r.error();
  NodeData nodes;
  if (facets) {
    *facets = GmshFacets();
    facets->known = (version >= 2.2 && version < 3.0) || (version >= 4.1 && version < 4.2);
    nodes.facets = facets;
  }
  const bool ok = version < 3.0 ? validateSections(r, nodes2, elements2, &nodes)
                                : validateSections(r, nodes4, elements4, &nodes, entities4);
  if (ok) *facts = nodes.facts();
  if (ok) nodes.finishFacets();
  if (!ok && facets) facets->known = false;
  return ok ? std::string() : r.error();
}

}  // namespace

PetscErrorCode validateGmshFile(MPI_Comm comm, const std::string &file, GmshFacts *facts, const std::string &option,
                                GmshFacets *facets) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  GmshFacts mine;
  if (facets) *facets = GmshFacets();
  const std::string err = rank == 0 ? validateFile(file, option, &mine, facets) : std::string();
  PetscCall(collectiveCheck(comm, !err.empty(), err));
  double packed[3] = {mine.coordinatesKnown ? 1.0 : 0.0, mine.zRange, mine.extent};
  PetscCallMPI(MPI_Bcast(packed, 3, MPI_DOUBLE, 0, comm));
  *facts = GmshFacts{packed[0] != 0.0, packed[1], packed[2]};
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
