// PLY header parsing.
#include <mccd/geometry/ply_format.h>

#include <limits>

#include <mccd/geometry/error.h>

#include <mccd/geometry/text_scan.h>

namespace mccd::detail {

Header parse_ply_header(const std::string& path, std::string_view text) {
  Header h;
  LineReader lines(text);
  std::string_view line, tok;
  auto at = [&] { return path + ": line " + std::to_string(lines.line_no()) + ": "; };
  if (!lines.next(line) || line != "ply")
    throw Error(path + ": header: not a PLY file (the first line must be 'ply')");
  // Lines end in "\n", "\r\n" or "\r". The header of a binary file written with lone "\r"
  // ends in one too, even when the first data byte is a "\n": the first line tells which.
  const bool lone_cr = text.size() > 3 && text[3] == '\r' && (text.size() == 4 || text[4] != '\n');
  bool have_format = false, ended = false;
  while (lines.next(line)) {
    Tokens toks(line);
    if (!toks.next(tok)) continue;
    if (tok == "comment" || tok == "obj_info") continue;
    if (tok == "end_header") {
      ended = true;
      break;
    }
    if (tok == "format") {
      std::string_view fmt;
      if (!toks.next(fmt)) throw Error(at() + "header: 'format' needs a value");
      if (fmt == "ascii") h.format = Format::Ascii;
      else if (fmt == "binary_little_endian") h.format = Format::BinaryLE;
      else if (fmt == "binary_big_endian") h.format = Format::BinaryBE;
      else
        throw Error(at() + "header: unknown format " + quote_tok(fmt) +
                    " (expected ascii, binary_little_endian or binary_big_endian)");
      have_format = true;
    } else if (tok == "element") {
      Element e;
      std::string_view name, count;
      if (!toks.next(name) || !toks.next(count))
        throw Error(at() + "header: expected 'element NAME COUNT'");
      std::int64_t n = 0;
      if (!parse_int(count, n) || n < 0)
        throw Error(at() + "header: expected a non-negative element count for " + quote_tok(name) + ", got " +
                    quote_tok(count));
      e.name = std::string(name);
      e.count = static_cast<std::uint64_t>(n);
      e.header_line = lines.line_no();
      for (const Element& other : h.elements)
        if (other.name == e.name) throw Error(at() + "header: duplicate element " + quote_tok(name));
      h.elements.push_back(std::move(e));
    } else if (tok == "property") {
      if (h.elements.empty()) throw Error(at() + "header: property before any element");
      Property p;
      std::string_view type;
      if (!toks.next(type)) throw Error(at() + "header: expected 'property TYPE NAME'");
      if (type == "list") {
        std::string_view ct, it;
        if (!toks.next(ct) || !toks.next(it))
          throw Error(at() + "header: expected 'property list COUNT_TYPE ITEM_TYPE NAME'");
        p.is_list = true;
        if (!scalar_from_name(ct, p.count_type)) throw Error(at() + "header: unknown property type " + quote_tok(ct));
        if (!scalar_from_name(it, p.type)) throw Error(at() + "header: unknown property type " + quote_tok(it));
        if (!is_integer(p.count_type))
          throw Error(at() + "header: the count type of a list must be an integer type, got " + quote_tok(ct));
      } else if (!scalar_from_name(type, p.type)) {
        throw Error(at() + "header: unknown property type " + quote_tok(type));
      }
      std::string_view name;
      if (!toks.next(name)) throw Error(at() + "header: property without a name");
      p.name = std::string(name);
      h.elements.back().props.push_back(std::move(p));
    } else {
      throw Error(at() + "header: unknown keyword " + quote_tok(tok));
    }
  }
  if (!ended) throw Error(path + ": header: missing 'end_header'");
  if (!have_format) throw Error(path + ": header: missing 'format' line");
  h.data_offset = lines.offset();
  const std::size_t line_end = static_cast<std::size_t>(line.data() + line.size() - text.data());
  if (lone_cr && h.format != Format::Ascii && line_end < text.size() && text[line_end] == '\r') h.data_offset = line_end + 1;
  h.data_line = lines.line_no() + 1;
  return h;
}

Layout make_layout(const std::string& path, const Header& h) {
  Layout L;
  for (std::size_t i = 0; i < h.elements.size(); ++i) {
    if (h.elements[i].name == "vertex") L.vertex_elem = static_cast<int>(i);
    if (h.elements[i].name == "face") L.face_elem = static_cast<int>(i);
  }
  if (L.vertex_elem < 0) throw Error(path + ": header: no 'vertex' element");
  const Element& ve = h.elements[L.vertex_elem];
  for (std::size_t p = 0; p < ve.props.size(); ++p)
    for (int k = 0; k < 3; ++k)
      if (ve.props[p].name == std::string(1, "xyz"[k])) {
        if (ve.props[p].is_list)
          throw Error(path + ": line " + std::to_string(ve.header_line) + ": header: vertex property '" +
                      ve.props[p].name + "' must be a scalar, not a list");
        L.xyz[k] = static_cast<int>(p);
      }
  for (int k = 0; k < 3; ++k)
    if (L.xyz[k] < 0) throw Error(path + ": header: element 'vertex' has no property '" + "xyz"[k] + "'");
  if (ve.count > std::numeric_limits<std::uint32_t>::max())
    throw Error(path + ": header: too many vertices (" + std::to_string(ve.count) + ")");
  if (L.face_elem >= 0) {
    const Element& fe = h.elements[L.face_elem];
    for (std::size_t p = 0; p < fe.props.size(); ++p)
      if (fe.props[p].name == "vertex_indices" || fe.props[p].name == "vertex_index") {
        if (!fe.props[p].is_list)
          throw Error(path + ": header: face property '" + fe.props[p].name + "' must be a list");
        if (!is_integer(fe.props[p].type))
          throw Error(path + ": header: face property '" + fe.props[p].name + "' must hold integers");
        L.indices = static_cast<int>(p);
        break;
      }
    if (L.indices < 0) throw Error(path + ": header: element 'face' has no list property 'vertex_indices'");
  }
  return L;
}

}  // namespace mccd::detail
