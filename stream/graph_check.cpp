#include <cxxabi.h>

#include <cstdlib>
#include <memory>

#include "stream/stage.hpp"

namespace meshless {

std::string graph_node_name(const std::type_info& t) {
    int status = 0;
    std::unique_ptr<char, void (*)(void*)> d(abi::__cxa_demangle(t.name(), nullptr, nullptr, &status), std::free);
    std::string name = status == 0 && d ? d.get() : t.name();
    const auto colon = name.rfind("::");
    return colon == std::string::npos ? name : name.substr(colon + 2);
}

Payload check_graph(const Source& source, std::span<const Stage* const> stages, const Sink& sink) {
    Payload p = source.gives();
    std::string from = graph_node_name(typeid(source));
    for (const Stage* s : stages) {
        const std::string name = graph_node_name(typeid(*s));
        if (!s->takes().has(p))
            throw GraphError("stage graph: " + name + " takes " + payload_names(s->takes()) + ", " + from + " gives " + payload_name(p));
        p = s->gives(p);
        from = name;
    }
    if (!sink.takes().has(p))
        throw GraphError("stage graph: " + graph_node_name(typeid(sink)) + " takes " + payload_names(sink.takes()) + ", " + from + " gives " + payload_name(p));
    return p;
}

}  // namespace meshless
