"""rqt_graph for a machine without rqt: the ROS computation graph (nodes, topics, connections)
from the master and each node's bus info, drawn with graphviz to PNG/SVG or shown in a window."""
