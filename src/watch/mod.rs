//! Watch mode: rebuild a project whenever it or a file it references changes.
//!
//! [`run`] watches the folders holding the project file, its meshes and the external buffers of
//! its `.gltf` meshes (non-recursively, so an editor's save by rename or by delete and re-create
//! keeps the watch), filters the debounced events by path ([`files`]), and calls a rebuild once
//! per burst of changes. A change that arrives while a rebuild runs sets the rebuild's
//! [`Cancel`] flag, so the rebuild gives up and the loop starts the next one with every change
//! since. The rebuild itself (compile, write, print) is the caller's: `ballast watch` passes one
//! that shares `build`'s code path and keeps one workspace for the session; [`changes`] says what
//! changed between good builds.

pub mod changes;
pub mod contents;
pub mod files;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, Receiver, TryRecvError};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use notify::{RecommendedWatcher, RecursiveMode};
use notify_debouncer_full::{new_debouncer, DebounceEventResult, Debouncer, RecommendedCache};

use crate::cancel::Cancel;

pub use changes::{differences, Snapshot};
pub use contents::Contents;
pub use files::{
    anchor_folders, folder_identity, is_change, referenced_files, touched, watch_key,
    watched_folders,
};

/// How long the file system must be quiet before a burst of events becomes one rebuild: long
/// enough to cover an editor's temp-file-and-rename save or a tool writing several files (each
/// takes a few milliseconds), short enough not to be felt. A burst that outlasts it starts a
/// rebuild that its next event cancels.
pub const DEBOUNCE: Duration = Duration::from_millis(40);

/// The exit status when Ctrl-C is pressed a second time while a rebuild runs: stop at once.
pub const EXIT_FORCED: i32 = 130;

/// What the watch loop hears: debounced file-system events, or Ctrl-C.
enum Message {
    Events(DebounceEventResult),
    Stop,
}

/// Watches `files`, rebuilds once, then rebuilds after every burst of changes to the watched
/// files, until Ctrl-C. A change is a file whose bytes are not those it held when the last
/// build reading it started ([`Contents`]): events that change no byte are ignored. `rebuild`
/// gets the changed files (none for the first build) and a flag that is set when a watched file
/// changes (or Ctrl-C is pressed) before it returns; it returns the files the project now
/// references (see [`referenced_files`]), and the watched folders follow that set. Changes made
/// during a build, the first one included, give one build after it, and so does a cancelled
/// build. Returns when Ctrl-C was pressed; an error when watching cannot start.
pub fn run(
    files: BTreeSet<PathBuf>,
    mut rebuild: impl FnMut(&[PathBuf], &Cancel) -> BTreeSet<PathBuf>,
) -> Result<(), String> {
    let (sender, receiver) = channel();
    let stop_sender = sender.clone();
    let stopping = Arc::new(AtomicBool::new(false));
    let flag = stopping.clone();
    let cancel = Cancel::new();
    let cancel_on_stop = cancel.clone();
    if let Err(error) = ctrlc::set_handler(move || {
        if flag.swap(true, Ordering::SeqCst) {
            // A second Ctrl-C while a rebuild runs: do not wait for it.
            std::process::exit(EXIT_FORCED);
        }
        cancel_on_stop.cancel();
        let _ = stop_sender.send(Message::Stop);
    }) {
        eprintln!("warning: cannot catch Ctrl-C ({error}); stop with a signal instead");
    }
    // The debouncer's thread cancels the rebuild in flight as soon as a watched file's bytes
    // change, before the main loop hears of it.
    let followed: Arc<Mutex<BTreeSet<PathBuf>>> = Arc::default();
    let contents: Arc<Mutex<Contents>> = Arc::default();
    let seen = followed.clone();
    let recorded = contents.clone();
    let cancel_on_change = cancel.clone();
    let mut debouncer = new_debouncer(DEBOUNCE, None, move |result: DebounceEventResult| {
        if let Ok(events) = &result {
            let files = lock(&seen);
            let mut touched_files = BTreeSet::new();
            for event in events.iter().filter(|event| is_change(&event.kind)) {
                touched_files.extend(touched(&event.paths, &files));
            }
            if !lock(&recorded).differing(&touched_files).is_empty() {
                cancel_on_change.cancel();
            }
        }
        let _ = sender.send(Message::Events(result));
    })
    .map_err(|error| format!("cannot watch files: {error}"))?;

    let mut watched = Watched {
        shared: followed,
        ..Watched::default()
    };
    watched.follow(&mut debouncer, files);
    if watched.folders.is_empty() {
        return Err("cannot watch the project's folder".to_string());
    }
    lock(&contents).record(&watched.files);
    let files = rebuild(&[], &cancel);
    // A cancelled build is owed one more, whether or not the bytes still differ.
    let mut owed = cancel.is_cancelled();
    watched.follow(&mut debouncer, files);
    loop {
        if stopping.load(Ordering::SeqCst) {
            return Ok(());
        }
        let Ok(message) = receiver.recv() else {
            return Ok(());
        };
        // Changes from here on cancel the coming rebuild; those before are part of it.
        cancel.reset();
        let mut changed = BTreeSet::new();
        if !take(message, &watched.files, &mut changed) {
            return Ok(());
        }
        if changed.is_empty() {
            continue;
        }
        // Everything already queued joins this rebuild.
        if !drain(&receiver, &watched.files, &mut changed) {
            return Ok(());
        }
        // A watched folder removed and made again needs a new watch: its old one ended with it.
        let files = watched.files.clone();
        watched.follow(&mut debouncer, files);
        let differing = {
            let mut contents = lock(&contents);
            let differing = contents.differing(&changed);
            contents.record(&differing);
            differing
        };
        let files = match (differing.is_empty(), owed) {
            (true, false) => continue,
            // Owed after a cancel, with nothing new: name what was touched.
            (true, true) => rebuild(&changed.into_iter().collect::<Vec<_>>(), &cancel),
            (false, _) => rebuild(&differing, &cancel),
        };
        owed = cancel.is_cancelled();
        watched.follow(&mut debouncer, files);
        if stopping.load(Ordering::SeqCst) {
            return Ok(());
        }
    }
}

/// The value behind `mutex`, even if a thread panicked holding it (the data stays usable).
fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Adds the watched files a message names to `changed`; `false` for Ctrl-C.
fn take(message: Message, files: &BTreeSet<PathBuf>, changed: &mut BTreeSet<PathBuf>) -> bool {
    match message {
        Message::Stop => false,
        Message::Events(Ok(events)) => {
            for event in events.iter().filter(|event| is_change(&event.kind)) {
                changed.extend(touched(&event.paths, files));
            }
            true
        }
        Message::Events(Err(errors)) => {
            for error in errors {
                eprintln!("warning: watching: {error}");
            }
            true
        }
    }
}

/// Takes every message already queued; `false` when one of them is Ctrl-C.
fn drain(
    receiver: &Receiver<Message>,
    files: &BTreeSet<PathBuf>,
    changed: &mut BTreeSet<PathBuf>,
) -> bool {
    loop {
        match receiver.try_recv() {
            Ok(message) => {
                if !take(message, files, changed) {
                    return false;
                }
            }
            Err(TryRecvError::Empty) => return true,
            Err(TryRecvError::Disconnected) => return false,
        }
    }
}

/// The files followed and the folders watched for them.
#[derive(Default)]
struct Watched {
    files: BTreeSet<PathBuf>,
    /// The folders watched for the files, each with the identity it had when its watch began.
    folders: BTreeMap<PathBuf, Option<(u64, u64)>>,
    /// Their parents, watched to see a watched folder removed and created again.
    anchors: BTreeMap<PathBuf, Option<(u64, u64)>>,
    /// The files, as the debouncer's thread sees them.
    shared: Arc<Mutex<BTreeSet<PathBuf>>>,
}

impl Watched {
    /// Follows `files` from now on: unwatches folders no longer needed, watches new ones, and
    /// watches again any that could not be watched before (a folder that did not exist) or that
    /// is not the folder it was (removed and created again).
    fn follow(
        &mut self,
        debouncer: &mut Debouncer<RecommendedWatcher, RecommendedCache>,
        files: BTreeSet<PathBuf>,
    ) {
        let wanted = watched_folders(&files);
        let anchors = anchor_folders(&wanted);
        self.folders = renew(debouncer, &self.folders, &wanted, true);
        self.anchors = renew(debouncer, &self.anchors, &anchors, false);
        if files != self.files {
            // A status line: on standard error, so standard output can carry JSON diagnostics.
            eprintln!("watching {}", list(&files));
        }
        *lock(&self.shared) = files.clone();
        self.files = files;
    }
}

/// The watches of `wanted` folders, given those `held` now: folders no longer wanted are
/// unwatched, and a folder is watched (again) unless it is held and still the folder its watch
/// began on. A folder that cannot be watched is left out (with a warning when `warn`), to be
/// tried again next time.
fn renew(
    debouncer: &mut Debouncer<RecommendedWatcher, RecommendedCache>,
    held: &BTreeMap<PathBuf, Option<(u64, u64)>>,
    wanted: &BTreeSet<PathBuf>,
    warn: bool,
) -> BTreeMap<PathBuf, Option<(u64, u64)>> {
    for folder in held.keys().filter(|folder| !wanted.contains(*folder)) {
        let _ = debouncer.unwatch(folder);
    }
    let mut watching = BTreeMap::new();
    for folder in wanted {
        let identity = folder_identity(folder);
        match held.get(folder) {
            Some(was) if identity.is_some() && *was == identity => {
                watching.insert(folder.clone(), identity);
                continue;
            }
            Some(_) => {
                let _ = debouncer.unwatch(folder);
            }
            None => {}
        }
        match debouncer.watch(folder, RecursiveMode::NonRecursive) {
            Ok(()) => {
                watching.insert(folder.clone(), identity);
            }
            Err(error) if warn => {
                eprintln!("warning: cannot watch {}: {error}", folder.display());
            }
            Err(_) => {}
        }
    }
    watching
}

/// File paths for a message, relative to the current folder when under it.
pub fn list(files: &BTreeSet<PathBuf>) -> String {
    files
        .iter()
        .map(|file| shown(file).display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// `path` relative to the current folder when under it.
pub fn shown(path: &Path) -> PathBuf {
    std::env::current_dir()
        .ok()
        .and_then(|here| here.canonicalize().ok())
        .and_then(|here| path.strip_prefix(here).ok().map(Path::to_path_buf))
        .unwrap_or_else(|| path.to_path_buf())
}

#[cfg(test)]
mod tests {
    use super::*;
    use notify::event::{AccessKind, AccessMode, CreateKind, ModifyKind, RenameMode};
    use notify::{Event, EventKind};
    use notify_debouncer_full::DebouncedEvent;
    use std::time::Instant;

    fn events(list: &[(EventKind, &[&str])]) -> Message {
        Message::Events(Ok(list
            .iter()
            .map(|(kind, paths)| {
                let mut event = Event::new(*kind);
                for path in *paths {
                    event = event.add_path(PathBuf::from(path));
                }
                DebouncedEvent::new(event, Instant::now())
            })
            .collect()))
    }

    fn watched() -> BTreeSet<PathBuf> {
        ["/p/model.kdl", "/p/meshes/t.obj"]
            .iter()
            .map(PathBuf::from)
            .collect()
    }

    #[test]
    fn queued_bursts_join_one_rebuild_and_reads_are_ignored() {
        let (sender, receiver) = channel();
        let rename = EventKind::Modify(ModifyKind::Name(RenameMode::Both));
        let read = EventKind::Access(AccessKind::Close(AccessMode::Read));
        sender
            .send(events(&[
                (EventKind::Create(CreateKind::File), &["/p/.model.kdl.swp"]),
                (rename, &["/p/.model.kdl.swp", "/p/model.kdl"]),
            ]))
            .unwrap();
        sender
            .send(events(&[(read, &["/p/meshes/t.obj"])]))
            .unwrap();
        sender
            .send(events(&[(
                EventKind::Create(CreateKind::File),
                &["/p/meshes/t.obj", "/p/build/model.glb"],
            )]))
            .unwrap();
        let mut changed = BTreeSet::new();
        assert!(drain(&receiver, &watched(), &mut changed));
        let changed: Vec<PathBuf> = changed.into_iter().collect();
        assert_eq!(
            changed,
            vec![
                PathBuf::from("/p/meshes/t.obj"),
                PathBuf::from("/p/model.kdl")
            ]
        );
    }

    #[test]
    fn ctrl_c_in_the_queue_stops() {
        let (sender, receiver) = channel();
        sender
            .send(events(&[(
                EventKind::Create(CreateKind::File),
                &["/p/model.kdl"],
            )]))
            .unwrap();
        sender.send(Message::Stop).unwrap();
        let mut changed = BTreeSet::new();
        assert!(!drain(&receiver, &watched(), &mut changed));
    }

    #[test]
    fn only_reads_give_nothing_to_rebuild() {
        let (sender, receiver) = channel();
        let open = EventKind::Access(AccessKind::Open(AccessMode::Any));
        sender.send(events(&[(open, &["/p/model.kdl"])])).unwrap();
        let mut changed = BTreeSet::new();
        assert!(drain(&receiver, &watched(), &mut changed));
        assert!(changed.is_empty());
    }
}
