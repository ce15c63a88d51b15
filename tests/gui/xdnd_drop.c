// tests/gui/xdnd_drop.c: a minimal XDND drag source that drops files on a window, for checking the viewer's file
// drops (ui/drop.h) by hand under Xvfb, where no file manager can drag. Not part of the build:
//   cc -O1 -o /tmp/xdnd_drop tests/gui/xdnd_drop.c -lX11
//   /tmp/xdnd_drop $(xdotool search --onlyvisible --name '^pathview' | head -1) 200 200 /abs/path/scene.gltf
// It sends XdndEnter/Position, drops on XdndStatus, answers the text/uri-list selection request, exits 0 on
// XdndFinished (1 if the window never finishes within 5 s).
#include <X11/Xatom.h>
#include <X11/Xlib.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
static Display* d;
static void send(Window target, Atom type, long l0, long l1, long l2, long l3, long l4) {
    XEvent e;
    memset(&e, 0, sizeof e);
    e.xclient.type = ClientMessage;
    e.xclient.display = d;
    e.xclient.window = target;
    e.xclient.message_type = type;
    e.xclient.format = 32;
    e.xclient.data.l[0] = l0;
    e.xclient.data.l[1] = l1;
    e.xclient.data.l[2] = l2;
    e.xclient.data.l[3] = l3;
    e.xclient.data.l[4] = l4;
    XSendEvent(d, target, False, NoEventMask, &e);
    XFlush(d);
}
int main(int argc, char** argv) {
    if (argc < 5) {
        fprintf(stderr, "usage: xdnd_drop WINDOW X Y FILE...\n");
        return 2;
    }
    d = XOpenDisplay(NULL);
    if (!d) return 1;
    Window target = strtoul(argv[1], NULL, 0);
    int x = atoi(argv[2]), y = atoi(argv[3]);
    char list[8192] = "";
    for (int i = 4; i < argc; ++i) {
        strcat(list, "file://");
        strcat(list, argv[i]);
        strcat(list, "\r\n");
    }
    Window src = XCreateSimpleWindow(d, DefaultRootWindow(d), 0, 0, 1, 1, 0, 0, 0);
    Atom aware = XInternAtom(d, "XdndAware", False), enter = XInternAtom(d, "XdndEnter", False),
         pos = XInternAtom(d, "XdndPosition", False), drop = XInternAtom(d, "XdndDrop", False),
         leave = XInternAtom(d, "XdndLeave", False), status = XInternAtom(d, "XdndStatus", False),
         finished = XInternAtom(d, "XdndFinished", False), sel = XInternAtom(d, "XdndSelection", False),
         uri = XInternAtom(d, "text/uri-list", False), copy = XInternAtom(d, "XdndActionCopy", False);
    (void)aware;
    (void)leave;
    XSetSelectionOwner(d, sel, src, CurrentTime);
    send(target, enter, (long)src, 5L << 24, (long)uri, 0, 0);
    send(target, pos, (long)src, 0, ((long)x << 16) | y, CurrentTime, (long)copy);
    int dropped = 0, done = 0;
    for (int spins = 0; spins < 500 && !done; ++spins) {
        while (XPending(d)) {
            XEvent e;
            XNextEvent(d, &e);
            if (e.type == ClientMessage && e.xclient.message_type == status && !dropped) {
                fprintf(stderr, "status accept=%ld\n", e.xclient.data.l[1] & 1);
                send(target, drop, (long)src, 0, CurrentTime, 0, 0);
                dropped = 1;
            } else if (e.type == SelectionRequest) {
                XSelectionRequestEvent* r = &e.xselectionrequest;
                XChangeProperty(d, r->requestor, r->property, r->target, 8, PropModeReplace, (unsigned char*)list,
                                (int)strlen(list));
                XEvent n;
                memset(&n, 0, sizeof n);
                n.xselection.type = SelectionNotify;
                n.xselection.requestor = r->requestor;
                n.xselection.selection = r->selection;
                n.xselection.target = r->target;
                n.xselection.property = r->property;
                n.xselection.time = r->time;
                XSendEvent(d, r->requestor, False, NoEventMask, &n);
                XFlush(d);
                fprintf(stderr, "sent %s", list);
            } else if (e.type == ClientMessage && e.xclient.message_type == finished) {
                fprintf(stderr, "finished\n");
                done = 1;
            }
        }
        usleep(10000);
    }
    XCloseDisplay(d);
    return done ? 0 : 1;
}
