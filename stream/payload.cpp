#include "stream/payload.hpp"

namespace meshless {

const char* payload_name(Payload p) {
    switch (p) {
        case Payload::cells: return "cell rows";
        case Payload::samples: return "samples";
        case Payload::points: return "points";
        case Payload::seeds: return "seeds";
        case Payload::mesh: return "mesh pieces";
        case Payload::queries: return "field queries";
    }
    return "?";
}

std::string payload_names(PayloadSet s) {
    std::string out;
    for (Payload p : {Payload::cells, Payload::samples, Payload::points, Payload::seeds, Payload::mesh, Payload::queries}) {
        if (!s.has(p)) continue;
        if (!out.empty()) out += " or ";
        out += payload_name(p);
    }
    return out.empty() ? "nothing" : out;
}

RecordKind record_kind_of(Payload p) {
    switch (p) {
        case Payload::cells:
        case Payload::samples: return RecordKind::sample;
        case Payload::points: return RecordKind::point;
        case Payload::seeds: return RecordKind::seed;
        case Payload::mesh: return RecordKind::mesh;
        case Payload::queries: return RecordKind::query;
    }
    return RecordKind::sample;
}

Payload payload_of(RecordKind k) {
    switch (k) {
        case RecordKind::sample: return Payload::samples;
        case RecordKind::point: return Payload::points;
        case RecordKind::seed: return Payload::seeds;
        case RecordKind::mesh: return Payload::mesh;
        case RecordKind::query: return Payload::queries;
    }
    return Payload::samples;
}

}  // namespace meshless
