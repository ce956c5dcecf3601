"""rqt_reconfigure for a machine without rqt: a PyQt5 editor for every dynamic_reconfigure server
on the master (sliders, check boxes, enums from the server's own description)."""
