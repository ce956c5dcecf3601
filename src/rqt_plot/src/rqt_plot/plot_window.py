"""The live-plot window: the plot (matplotlib in Qt), a field to add series, Pause, Clear and
the window width; redrawn ten times a second."""
from matplotlib.backends.backend_qt5agg import FigureCanvasQTAgg
from matplotlib.figure import Figure
from PyQt5 import QtCore, QtWidgets

from rqt_plot.errors import PlotError
from rqt_plot.series import draw


class _Bridge(QtCore.QObject):
    message = QtCore.pyqtSignal(str)


class PlotWindow(QtWidgets.QWidget):
    def __init__(self, store, add_series, width, title="", parent=None):
        """``add_series(spec)`` adds a series (PlotRecorder.add); ``width``: rolling window in s."""
        QtWidgets.QWidget.__init__(self, parent)
        self.setWindowTitle("Plot")
        self.store = store
        self.add_series = add_series
        self.title = title
        self.bridge = _Bridge()
        self.bridge.message.connect(self.show_message)
        self.topic = QtWidgets.QLineEdit()
        self.topic.setPlaceholderText("/topic/field[index]  (Enter adds it)")
        self.topic.returnPressed.connect(self._add)
        add = QtWidgets.QPushButton("+")
        add.clicked.connect(self._add)
        self.pause = QtWidgets.QCheckBox("Pause")
        clear = QtWidgets.QPushButton("Clear")
        clear.clicked.connect(self.store.clear)
        self.width = QtWidgets.QDoubleSpinBox()
        self.width.setRange(0.0, 36000.0)
        self.width.setDecimals(1)
        self.width.setSuffix(" s")
        self.width.setSpecialValueText("all")
        self.width.setValue(width)
        bar = QtWidgets.QHBoxLayout()
        bar.addWidget(QtWidgets.QLabel("Topic"))
        bar.addWidget(self.topic, 1)
        bar.addWidget(add)
        bar.addWidget(self.pause)
        bar.addWidget(clear)
        bar.addWidget(QtWidgets.QLabel("window"))
        bar.addWidget(self.width)
        self.figure = Figure(figsize=(9, 5), dpi=100)
        self.canvas = FigureCanvasQTAgg(self.figure)
        self.status = QtWidgets.QLabel("")
        self.status.setWordWrap(True)
        self.status.setSizePolicy(QtWidgets.QSizePolicy.Ignored, QtWidgets.QSizePolicy.Preferred)
        layout = QtWidgets.QVBoxLayout(self)
        layout.addLayout(bar)
        layout.addWidget(self.canvas, 1)
        layout.addWidget(self.status)
        self.resize(1000, 620)
        self.timer = QtCore.QTimer(self)
        self.timer.timeout.connect(self.redraw)
        self.timer.start(100)

    def show_message(self, text):
        self.status.setText(text)

    def redraw(self):
        if self.pause.isChecked():
            return
        draw(self.figure, self.store, self.width.value(), self.title)
        self.canvas.draw_idle()

    def _add(self):
        spec = self.topic.text().strip()
        if not spec:
            return
        try:
            names = self.add_series(spec)
        except PlotError as err:
            self.show_message(str(err))
            return
        self.topic.clear()
        self.show_message("added %s" % ", ".join(names))
