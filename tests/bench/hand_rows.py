"""A hand-made results table: three detectors, two tasks, two seeds, one failed cell."""

#: ROC AUC by detector, task and seed; None: the cell failed
AUC = {
    "ref": {("t1", 0): 0.80, ("t1", 1): 0.70, ("t2", 0): 0.60, ("t2", 1): 0.90},
    "a": {("t1", 0): 0.90, ("t1", 1): 0.70, ("t2", 0): 0.50, ("t2", 1): None},
    "b": {("t1", 0): 0.85, ("t1", 1): 0.75, ("t2", 0): 0.70, ("t2", 1): 0.95},
}


def rows_of(table):
    rows = []
    for detector, cells in table.items():
        for (task, seed), auc in cells.items():
            status = "ok" if auc is not None else "error"
            rows.append({"cell_id": f"{detector}-{task}-{seed}", "detector": detector, "task": task,
                         "seed": seed, "status": status, "roc_auc": auc,
                         "error": "" if auc is not None else "RuntimeError: boom"})
    return rows
