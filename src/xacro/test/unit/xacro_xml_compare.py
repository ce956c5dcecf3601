"""XML compared as xacro's own tests compare it: elements, attributes and text; comments and
blank text ignored."""
import xml.dom
import xml.dom.minidom


def _node(node):
    if node.nodeType == xml.dom.Node.ELEMENT_NODE:
        children = [c for c in (_node(c) for c in node.childNodes) if c is not None]
        return (node.tagName, sorted(node.attributes.items()), children)
    if node.nodeType in (xml.dom.Node.TEXT_NODE, xml.dom.Node.CDATA_SECTION_NODE):
        text = " ".join(node.data.split())
        return text or None
    return None


def canonical(doc_or_text):
    """A comparable form of a DOM document, element or XML text."""
    if isinstance(doc_or_text, str):
        doc_or_text = xml.dom.minidom.parseString(doc_or_text)
    if doc_or_text.nodeType == xml.dom.Node.DOCUMENT_NODE:
        doc_or_text = doc_or_text.documentElement
    return _node(doc_or_text)
