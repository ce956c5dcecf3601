"""The expanded document as text, laid out as xacro writes it: two-space indentation, attributes
in alphabetical order, blank text dropped, an element whose only child is text on one line."""
import xml.dom

N = xml.dom.Node


def _escape(text, quote=False):
    text = text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    return text.replace('"', "&quot;") if quote else text


def _write(node, out, indent):
    kind = node.nodeType
    if kind == N.ELEMENT_NODE:
        attrs = "".join(' %s="%s"' % (name, _escape(node.getAttribute(name), quote=True))
                        for name in sorted(node.attributes.keys()))
        children = node.childNodes
        if not children:
            out.append("%s<%s%s/>\n" % (indent, node.tagName, attrs))
        elif len(children) == 1 and children[0].nodeType == N.TEXT_NODE:
            out.append("%s<%s%s>%s</%s>\n" % (indent, node.tagName, attrs, _escape(children[0].data),
                                              node.tagName))
        else:
            out.append("%s<%s%s>\n" % (indent, node.tagName, attrs))
            for child in children:
                if child.nodeType == N.TEXT_NODE and (not child.data or child.data.isspace()):
                    continue
                _write(child, out, indent + "  ")
            out.append("%s</%s>\n" % (indent, node.tagName))
    elif kind == N.TEXT_NODE:
        out.append("%s%s\n" % (indent, _escape(node.data)))
    elif kind == N.CDATA_SECTION_NODE:
        out.append("%s<![CDATA[%s]]>\n" % (indent, node.data))
    elif kind == N.COMMENT_NODE:
        out.append("%s<!--%s-->\n" % (indent, node.data))
    elif kind == N.PROCESSING_INSTRUCTION_NODE:
        out.append("%s<?%s %s?>\n" % (indent, node.target, node.data))
    elif kind == N.DOCUMENT_NODE:
        out.append('<?xml version="1.0" ?>\n')
        for child in node.childNodes:
            _write(child, out, indent)


def to_xml(doc):
    """The document (or element) as indented XML text."""
    out = []
    _write(doc, out, "")
    return "".join(out)
