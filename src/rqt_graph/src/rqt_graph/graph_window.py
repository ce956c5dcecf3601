"""The node-graph window: rqt_graph's check boxes above, the picture below (fit to the window or
1:1 with scroll bars), Refresh and Save (PNG, SVG, PDF or DOT by the file name)."""
from PyQt5 import QtCore, QtGui, QtWidgets

from rqt_graph import render
from rqt_graph.errors import GraphError
from rqt_graph.graph_model import Options, build_graph, to_dot

MODE_LABELS = (("nodes_topics", "Nodes/Topics (all)"), ("nodes", "Nodes only"))


class GraphWindow(QtWidgets.QWidget):
    """``take_snapshot()`` returns a SystemSnapshot (ros_graph.snapshot in use, fixed data in tests)."""

    def __init__(self, take_snapshot, opts, parent=None):
        QtWidgets.QWidget.__init__(self, parent)
        self.setWindowTitle("Node Graph")
        self.take_snapshot = take_snapshot
        self.dot_text = ""
        self.png = None
        self.mode = QtWidgets.QComboBox()
        for key, label in MODE_LABELS:
            self.mode.addItem(label, key)
        self.mode.setCurrentIndex([k for k, _ in MODE_LABELS].index(opts.mode))
        self.filter = QtWidgets.QLineEdit(opts.filter)
        self.filter.setPlaceholderText("filter: words to show, -word to hide")
        self.checks = {}
        for key, label in (("group_namespaces", "Group namespaces"), ("hide_debug", "Hide debug"),
                           ("hide_tf", "Hide tf"), ("hide_leaf_topics", "Hide leaf topics"),
                           ("hide_dead_sinks", "Hide dead sinks"), ("hide_params", "Hide params")):
            box = QtWidgets.QCheckBox(label)
            box.setChecked(getattr(opts, key))
            box.toggled.connect(self.redraw)
            self.checks[key] = box
        self.fit = QtWidgets.QCheckBox("Fit")
        self.fit.setChecked(True)
        self.fit.toggled.connect(self._show_image)
        refresh = QtWidgets.QPushButton("Refresh")
        refresh.clicked.connect(self.refresh)
        save = QtWidgets.QPushButton("Save ...")
        save.clicked.connect(self._save_dialog)
        self.mode.currentIndexChanged.connect(self.redraw)
        self.filter.editingFinished.connect(self.redraw)

        bar1 = QtWidgets.QHBoxLayout()
        bar1.addWidget(refresh)
        bar1.addWidget(self.mode)
        bar1.addWidget(self.filter, 1)
        bar1.addWidget(save)
        bar2 = QtWidgets.QHBoxLayout()
        for box in self.checks.values():
            bar2.addWidget(box)
        bar2.addWidget(self.fit)
        bar2.addStretch(1)
        self.image = QtWidgets.QLabel()
        self.image.setAlignment(QtCore.Qt.AlignCenter)
        self.image.setBackgroundRole(QtGui.QPalette.Base)
        self.scroll = QtWidgets.QScrollArea()
        self.scroll.setWidget(self.image)
        self.scroll.setAlignment(QtCore.Qt.AlignCenter)
        self.status = QtWidgets.QLabel("")
        self.status.setWordWrap(True)
        self.status.setSizePolicy(QtWidgets.QSizePolicy.Ignored, QtWidgets.QSizePolicy.Preferred)
        layout = QtWidgets.QVBoxLayout(self)
        layout.addLayout(bar1)
        layout.addLayout(bar2)
        layout.addWidget(self.scroll, 1)
        layout.addWidget(self.status)
        self.snap = None
        self.resize(1100, 750)

    def options(self):
        return Options(mode=self.mode.currentData(), filter=self.filter.text(),
                       **{k: b.isChecked() for k, b in self.checks.items()})

    def refresh(self):
        try:
            self.snap = self.take_snapshot()
        except GraphError as err:
            self.status.setText(str(err))
            return
        self.redraw()

    def redraw(self):
        if self.snap is None:
            return
        opts = self.options()
        graph = build_graph(self.snap, opts)
        self.dot_text = to_dot(graph, opts)
        try:
            self.png = render.render_bytes(self.dot_text, "png")
        except GraphError as err:
            self.status.setText(str(err))
            return
        self.status.setText("%d nodes, %d topics, %d edges (%d live)"
                            % (len(graph.nodes), len(graph.topics), len(graph.edges), len(graph.live)))
        self._show_image()

    def _show_image(self):
        if not self.png:
            return
        pix = QtGui.QPixmap()
        pix.loadFromData(self.png, "PNG")
        policy = QtCore.Qt.ScrollBarAlwaysOff if self.fit.isChecked() else QtCore.Qt.ScrollBarAsNeeded
        self.scroll.setHorizontalScrollBarPolicy(policy)
        self.scroll.setVerticalScrollBarPolicy(policy)
        if self.fit.isChecked():
            area = self.scroll.viewport().size()
            if pix.width() > area.width() or pix.height() > area.height():
                pix = pix.scaled(area, QtCore.Qt.KeepAspectRatio, QtCore.Qt.SmoothTransformation)
        self.image.setPixmap(pix)
        self.image.resize(pix.size())

    def resizeEvent(self, event):
        QtWidgets.QWidget.resizeEvent(self, event)
        self._show_image()

    def _save_dialog(self):
        path, _ = QtWidgets.QFileDialog.getSaveFileName(self, "Save graph", "rosgraph.png",
                                                        "Images (*.png *.svg *.pdf);;DOT (*.dot)")
        if path:
            self.save(path)

    def save(self, path):
        try:
            render.write(self.dot_text, path)
            self.status.setText("saved %s" % path)
        except GraphError as err:
            self.status.setText(str(err))
